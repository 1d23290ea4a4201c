// Run time of the engine (Google Benchmark 1.7). Counters: dof_steps/s (degrees of freedom ×
// steps per second), runs/s for sweeps. bench/report prints the ratios of one run.
#include <benchmark/benchmark.h>
#include <immintrin.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>
#include <vector>

#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/common/function_versions.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"
#include "sparse_reference.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

// The defaults of method `index` of method_registry(): the benchmarks that time methods take
// every registered one by its index there, so a new method is timed without a line here.
const MethodDescriptor& registered_method(std::int64_t index) {
  return method_registry()[static_cast<std::size_t>(index)];
}

MethodParams registered_defaults(std::int64_t index) {
  return std::get<MethodParams>(registered_method(index).make(MethodArguments{}));
}

// Args 0 … (registered methods − 1).
void every_registered_method(benchmark::internal::Benchmark* b) {
  b->DenseRange(0, static_cast<int>(method_registry().size()) - 1);
}

void set_dof_counters(benchmark::State& state, const RodScene& scene, double runs) {
  const RodSceneDerived d = derive(scene);
  const double dof_steps = (scene.elements + 1.0) * static_cast<double>(d.step_count);
  state.counters["dof_steps/s"] = benchmark::Counter(dof_steps * runs, benchmark::Counter::kIsRate);
  state.counters["steps"] = static_cast<double>(d.step_count);
}

// One simulation of the default scene (201 dof, 1222 steps) with each registered method's
// defaults, through simulate(): set-up and stepping, no indicators. Arg: the method's index in
// method_registry() (3 is HHT, which bench/report reads).
void BM_Run(benchmark::State& state) {
  const RodScene scene;
  const MethodParams method = registered_defaults(state.range(0));
  SimulationWorkspace workspace;
  RunSummary s;
  for (auto _ : state) {
    s = simulate(scene, method, RunOptions{}, workspace);
    benchmark::DoNotOptimize(s.final_energy);
  }
  // A method whose defaults go unstable here (Wilson-θ's) stops early, while the counters count
  // the whole run's dof-steps: the label says where it stopped (BM_WholeRunDofStep steps it
  // through).
  std::string label = registered_method(state.range(0)).name;
  if (s.status != RunStatus::ok)
    label += std::string(", ") + to_string(s.status) + " at step " + std::to_string(s.steps);
  state.SetLabel(label);
  set_dof_counters(state, scene, static_cast<double>(state.iterations()));
}
BENCHMARK(BM_Run)->Apply(every_registered_method)->Unit(benchmark::kMicrosecond);

// Time per dof-step of scenes of bodies against the paper's scene, each run through
// simulate(AssembledScene) with HHT's defaults (set-up and stepping, no indicators): 0 the paper's
// scene (through the scene path, which is the rod's own code), 1 two equal rods of 200 elements
// (402 dof, one contact between bodies), 2 a five-segment stepped rod on a wall (200 elements,
// areas 1, 2, 4, 2, 1). Counter ns/dof-step.
Scene benchmark_scene(int index) {
  if (index == 0) return to_scene(RodScene{});
  Scene s;
  if (index == 1) {
    const Segment rod{.length = 20.0, .elements = 200};
    s.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {rod}},
                Body{.name = "target", .gap = 0.01, .segments = {rod}}};
    return s;
  }
  Body rod{.name = "rod", .velocity = 1000.0};
  for (const double area : {1.0, 2.0, 4.0, 2.0, 1.0}) {
    rod.segments.push_back(Segment{.length = 4.0, .elements = 40, .area = area});
  }
  s.bodies = {rod};
  s.right_wall = Wall{.gap = 0.01};
  return s;
}

void BM_SceneRun(benchmark::State& state) {
  const Scene scene = benchmark_scene(static_cast<int>(state.range(0)));
  const AssembledScene assembled = assemble(scene);
  state.SetLabel(state.range(0) == 0 ? "paper" : state.range(0) == 1 ? "two-rods" : "stepped-5");
  SimulationWorkspace workspace;
  long stepped = 0;
  for (auto _ : state) {
    const RunSummary s = simulate(assembled, HhtParams{}, RunOptions{}, workspace);
    stepped += s.steps - s.skipped_steps;
    benchmark::DoNotOptimize(s.final_energy);
  }
  const double dof_steps =
      static_cast<double>(assembled.system.size()) * static_cast<double>(stepped);
  state.counters["ns/dof-step"] = benchmark::Counter(
      dof_steps * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SceneRun)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

// The same scenes through the batched kernels, kBatchLanes HHT runs with α = −0.5·(l + 1)/
// kBatchLanes in lane l (δ = −α): the paper's scene through the rod's kernel
// (core/batch/batched_simulation.hpp), the others through the chain kernel
// (core/batch/batched_chain.hpp). Counter ns/dof-step: per lane, over the samples each lane
// stepped.
void BM_SceneBatchedRun(benchmark::State& state) {
  const int index = static_cast<int>(state.range(0));
  const Scene scene = benchmark_scene(index);
  const AssembledScene assembled = assemble(scene);
  state.SetLabel(index == 0 ? "paper" : index == 1 ? "two-rods" : "stepped-5");
  std::vector<MethodParams> methods;
  for (int l = 0; l < kBatchLanes; ++l) {
    methods.push_back(HhtParams{.alpha = -0.5 * (l + 1) / kBatchLanes});
  }
  const std::vector<RodScene> rods(kBatchLanes);
  const std::vector<const AssembledScene*> scenes(kBatchLanes, &assembled);
  BatchWorkspace rod_workspace;
  ChainBatchWorkspace chain_workspace;
  std::vector<RunSummary> summaries(kBatchLanes);
  double dof_steps = 0.0;
  for (auto _ : state) {
    if (index == 0) {
      simulate_batch(rods, methods, RunOptions{}, rod_workspace, summaries);
    } else {
      simulate_chain_batch(scenes, methods, RunOptions{}, chain_workspace, summaries);
    }
    for (const RunSummary& s : summaries) {
      dof_steps += static_cast<double>(assembled.system.size()) *
                   static_cast<double>(s.steps - s.skipped_steps);
    }
    benchmark::DoNotOptimize(summaries[0].final_energy);
  }
  state.counters["lanes"] = kBatchLanes;
  state.counters["ns/dof-step"] = benchmark::Counter(
      dof_steps * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SceneBatchedRun)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

// Time per dof-step of one registered method's defaults on the default scene (201 dof, 1222
// steps): kBatchLanes runs of it through the rod's batched kernel when `batched` (the method must
// be batchable), one run through simulate() otherwise. Counter ns/dof-step per run (per lane,
// over the samples each run stepped: a run that ends unstable early counts the samples it
// stepped).
void time_dof_step(benchmark::State& state, const MethodParams& params, const RunOptions& options,
                   bool batched) {
  const RodScene scene;
  const std::vector<RodScene> scenes(kBatchLanes, scene);
  const std::vector<MethodParams> methods(kBatchLanes, params);
  std::vector<RunSummary> summaries(batched ? kBatchLanes : 1);
  BatchWorkspace batch_workspace;
  SimulationWorkspace workspace;
  double dof_steps = 0.0;
  for (auto _ : state) {
    if (batched) {
      simulate_batch(scenes, methods, options, batch_workspace, summaries);
    } else {
      summaries[0] = simulate(scene, params, options, workspace);
    }
    for (const RunSummary& s : summaries) {
      dof_steps += (scene.elements + 1.0) * static_cast<double>(s.steps - s.skipped_steps);
    }
    benchmark::DoNotOptimize(summaries[0].final_energy);
  }
  state.counters["ns/dof-step"] = benchmark::Counter(
      dof_steps * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Every method of the registry with its defaults on the default scene, on the path a sweep takes
// it: batched where it is batchable (core/batch/batched_simulation.hpp), one run through
// simulate() otherwise. Arg: its index in method_registry(). Counters: ns/dof-step, stages,
// batched. bench/report prints each method's time per dof-step and its ratio to HHT's per stage.
void BM_MethodDofStep(benchmark::State& state) {
  const MethodDescriptor& method = registered_method(state.range(0));
  const MethodParams params = registered_defaults(state.range(0));
  const bool batched = batchable(RodScene{}, params, RunOptions{});
  state.SetLabel(std::string(method.name) + (batched ? " batched" : " scalar"));
  time_dof_step(state, params, RunOptions{}, batched);
  state.counters["stages"] = method.stages;
  state.counters["batched"] = batched ? 1.0 : 0.0;
}
BENCHMARK(BM_MethodDofStep)->Apply(every_registered_method)->Unit(benchmark::kMicrosecond);

// The same over whole runs: a method whose defaults go unstable in the default scene (Wilson-θ's
// after about 50 steps, REPRODUCTION.md) stops early, so BM_MethodDofStep's figure for it mostly
// measures a batch's set-up. Here the energy bound is lifted (1000·E0), so that its runs step
// their samples as a stable point of a sweep does; a stable method's figure is BM_MethodDofStep's.
// Args: the method's index in method_registry(); 0 the sweep's path (batched where batchable),
// 1 one run through simulate(). Counter: ns/dof-step per run, as BM_MethodDofStep's.
void BM_WholeRunDofStep(benchmark::State& state) {
  const MethodDescriptor& method = registered_method(state.range(0));
  const MethodParams params = registered_defaults(state.range(0));
  const RunOptions options{.energy_growth_limit = 1000.0};
  const bool batched = state.range(1) == 0 && batchable(RodScene{}, params, options);
  state.SetLabel(std::string(method.name) + (batched ? " batched" : " scalar") + ", bound lifted");
  time_dof_step(state, params, options, batched);
}
BENCHMARK(BM_WholeRunDofStep)
    ->ArgsProduct(
        {benchmark::CreateDenseRange(0, static_cast<int>(method_registry().size()) - 1, 1), {0, 1}})
    ->Unit(benchmark::kMicrosecond);

// What each skip saves: HHT on a scene with a long free flight (gap 0.2 mm: 428 of 1650 steps
// before the impact). 0: every skip on (the defaults); 1: free flight stepped; 2: energy checked
// every step; 3: histories recorded (displacement and energy at every sample); 4: none.
void BM_Skips(benchmark::State& state) {
  RodScene scene;
  scene.gap = 0.2;
  RunOptions options;
  const int variant = static_cast<int>(state.range(0));
  if (variant == 1 || variant == 4) options.skip_free_flight = false;
  if (variant == 2 || variant == 4) options.energy_check_interval = 1;
  if (variant == 3 || variant == 4) options.record_history = true;
  const char* labels[] = {"all skips", "free flight stepped", "energy every step",
                          "histories recorded", "no skip"};
  state.SetLabel(labels[variant]);
  SimulationWorkspace workspace;
  for (auto _ : state) {
    benchmark::DoNotOptimize(simulate(scene, HhtParams{}, options, workspace).final_energy);
  }
  set_dof_counters(state, scene, static_cast<double>(state.iterations()));
}
BENCHMARK(BM_Skips)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);

// A simulation and its indicators, as a sweep point computes them.
void BM_Evaluate(benchmark::State& state) {
  SimulationSettings settings;
  const Simulation sim = std::get<Simulation>(build(settings));
  SimulationWorkspace workspace;
  for (auto _ : state) benchmark::DoNotOptimize(evaluate(sim, workspace).indicators.eps_p);
  state.SetLabel("hht, default scene");
}
BENCHMARK(BM_Evaluate)->Unit(benchmark::kMicrosecond);

// The indicators alone (eq. 18's errors, the peak counts, p_max, the contact episodes) from the
// trace of a finished run of the default scene: what a sweep point costs beyond its run. Arg:
// 100·δ of HHT with α = −0.3: δ = 0.3 (72 pressure peaks), 0.45 (the period-error relation
// δ = −1.5α: 19) and 0.8 (7); the label gives the counts.
void BM_Indicators(benchmark::State& state) {
  const RodScene scene;
  const double delta = static_cast<double>(state.range(0)) / 100.0;
  SimulationWorkspace workspace;
  const RunSummary summary =
      simulate(scene, HhtParams{.alpha = -0.3, .delta = delta}, RunOptions{}, workspace);
  Indicators indicators{};
  for (auto _ : state) {
    indicators = evaluate_indicators(scene, workspace.trace, summary, IndicatorOptions{});
    benchmark::DoNotOptimize(indicators.eps_p);
  }
  state.SetLabel("hht, delta " + std::to_string(delta).substr(0, 4) + ": nop_p " +
                 std::to_string(static_cast<long>(indicators.nop_p)) + ", nop_v " +
                 std::to_string(static_cast<long>(indicators.nop_v)));
}
BENCHMARK(BM_Indicators)->Arg(30)->Arg(45)->Arg(80)->Unit(benchmark::kMicrosecond);

// The indicators of a batch's kBatchLanes runs of one scene together (HHT, α = −0.3, δ from 0.3
// to 1.05), as evaluate_batch computes them; time per run = time / lanes.
void BM_IndicatorsOfABatch(benchmark::State& state) {
  const RodScene scene;
  std::vector<SimulationWorkspace> runs(kBatchLanes);
  std::vector<const ContactTrace*> traces;
  std::vector<RunSummary> summaries;
  for (int l = 0; l < kBatchLanes; ++l) {
    summaries.push_back(simulate(scene, HhtParams{.alpha = -0.3, .delta = 0.3 + 0.05 * l},
                                 RunOptions{}, runs[static_cast<std::size_t>(l)]));
    traces.push_back(&runs[static_cast<std::size_t>(l)].trace);
  }
  const std::vector<IndicatorOptions> options(kBatchLanes);
  std::vector<Indicators> indicators(kBatchLanes);
  for (auto _ : state) {
    evaluate_indicators(scene, traces, summaries, options, indicators);
    benchmark::DoNotOptimize(indicators[0].eps_p);
  }
  state.counters["lanes"] = kBatchLanes;
}
BENCHMARK(BM_IndicatorsOfABatch)->Unit(benchmark::kMicrosecond);

// Sweep throughput: 64 HHT points over (δ, α) on 1 and 2 threads, a workspace per thread.
void BM_Sweep(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  constexpr int kPoints = 64;
  for (auto _ : state) {
#pragma omp parallel num_threads(threads)
    {
      SimulationWorkspace workspace;
#pragma omp for schedule(dynamic, 1)
      for (int k = 0; k < kPoints; ++k) {
        SimulationSettings s;
        s.method.given.set("alpha", -0.5 * (k % 8) / 7.0);
        s.method.given.set("delta", 0.3 + 0.1 * (k / 8));
        benchmark::DoNotOptimize(evaluate(std::get<Simulation>(build(s)), workspace));
      }
    }
  }
  state.counters["runs/s"] = benchmark::Counter(kPoints * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  set_dof_counters(state, RodScene{}, kPoints * static_cast<double>(state.iterations()));
}
BENCHMARK(BM_Sweep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The batched kernel (core/batch/batched_simulation.hpp): kBatchLanes HHT runs of the default scene
// with α = −0.5·(l + 1)/kBatchLanes in lane l, from −0.03 to −0.5 (δ = −α), set-up and
// stepping, no indicators.
// Time per run = time / lanes (a lane that stops early still costs its lane until the batch
// ends).
void BM_BatchedRun(benchmark::State& state) {
  const std::vector<RodScene> scenes(kBatchLanes);
  std::vector<MethodParams> methods;
  for (int l = 0; l < kBatchLanes; ++l) {
    methods.push_back(HhtParams{.alpha = -0.5 * (l + 1) / kBatchLanes});
  }
  BatchWorkspace workspace;
  std::vector<RunSummary> summaries(kBatchLanes);
  for (auto _ : state) {
    simulate_batch(scenes, methods, RunOptions{}, workspace, summaries);
    benchmark::DoNotOptimize(summaries[0].final_energy);
  }
  state.SetLabel("hht x " + std::to_string(kBatchLanes) + " lanes");
  state.counters["lanes"] = kBatchLanes;
  state.counters["runs/s"] = benchmark::Counter(
      kBatchLanes * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  set_dof_counters(state, RodScene{}, kBatchLanes * static_cast<double>(state.iterations()));
}
// On 1 thread, and on 2 at once (one batch per core, each with its own workspace): the time per
// run per core inside a sweep that keeps both cores busy. Five repetitions, because these are
// the figures the 100 µs target is read from and the machines here are shared: bench/report
// gives their minimum and median.
constexpr int kTargetRepetitions = 5;
BENCHMARK(BM_BatchedRun)
    ->Unit(benchmark::kMicrosecond)
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime()
    ->Repetitions(kTargetRepetitions);

// BM_Sweep's domain of HHT points, at eight times its δ resolution (512 points, 8 α × 64 δ from
// 0.3 to 0.99), through evaluate_batch, kBatchLanes points per unit of work, as run_sweep
// groups them. Why more points than BM_Sweep: with 4 units per iteration each thread ran 2
// and then waited for the other, so on this shared machine, where one core is often slower
// than the other for minutes, the figure was the slower core's, well above a whole `impactid
// run` sweep's with its 212 dynamically scheduled units. Batches whose lanes all end unstable stop
// early, as in a sweep.
void BM_BatchedSweep(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  constexpr int kPoints = 512;
  std::vector<Simulation> simulations;
  for (int k = 0; k < kPoints; ++k) {
    SimulationSettings s;
    s.method.given.set("alpha", -0.5 * (k % 8) / 7.0);
    s.method.given.set("delta", 0.3 + 0.7 * (k / 8) / 64.0);
    simulations.push_back(std::get<Simulation>(build(s)));
  }
  constexpr int kUnits = (kPoints + kBatchLanes - 1) / kBatchLanes;
  // One workspace per thread for all iterations, as run_sweep keeps one per thread for the whole
  // sweep. (Made afresh at every iteration, they made each iteration pay for allocating them,
  // which a real sweep does once.)
  std::vector<BatchEvaluationWorkspace> workspaces(static_cast<std::size_t>(threads));
  std::vector<std::vector<Evaluation>> outs(static_cast<std::size_t>(threads),
                                            std::vector<Evaluation>(kBatchLanes));
  for (auto _ : state) {
#pragma omp parallel num_threads(threads)
    {
      const auto thread = static_cast<std::size_t>(omp_get_thread_num());
      std::vector<Evaluation>& out = outs[thread];
#pragma omp for schedule(dynamic, 1)
      for (int u = 0; u < kUnits; ++u) {
        const int first = u * kBatchLanes, count = std::min(kBatchLanes, kPoints - first);
        evaluate_batch(std::span(simulations).subspan(first, count), workspaces[thread],
                       std::span(out).first(count));
        benchmark::DoNotOptimize(out[0].indicators.eps_p);
      }
    }
  }
  state.counters["runs/s"] = benchmark::Counter(kPoints * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  set_dof_counters(state, RodScene{}, kPoints * static_cast<double>(state.iterations()));
}
BENCHMARK(BM_BatchedSweep)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Repetitions(kTargetRepetitions);

// The core clock under load: a chain of dependent integer adds retires one add per cycle, so
// adds/s is cycles/s (turbo included, which /proc/cpuinfo's nominal MHz is not).
void BM_Clock(benchmark::State& state) {
  constexpr long kAdds = 8 * 1'000'000;
  for (auto _ : state) {
    std::uint64_t x = 0;
    for (long i = 0; i < kAdds / 8; ++i) {
      asm volatile(
          "add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\t"
          "add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0"
          : "+r"(x));
    }
    benchmark::DoNotOptimize(x);
  }
  state.counters["Hz"] = benchmark::Counter(kAdds * static_cast<double>(state.iterations()),
                                            benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Clock)->Unit(benchmark::kMillisecond);

// The kernels' own arithmetic ceiling at the level that runs (core/common/kernel_level.hpp):
// independent chains a = a·m + c on the level's registers, once with a separate multiply and add
// (as -ffp-contract=off issues a·m + c) and once fused, as the kernels issue their multiply-adds.
// x86-64-v4: 16 chains of 8 doubles (AVX-512 has 32 registers); x86-64-v3: 12 chains of 4
// doubles (AVX2 has 16: 12 chains, m and c stay in registers); baseline: 12 chains of 2 doubles
// (SSE2; no fused instruction: std::fma is a library call there). Enough chains to cover the
// latency of two FMA units. The chains are named variables, not an array: GCC keeps an array
// indexed in a loop on the stack, and the loads and stores then bound the loop. flops/s ÷ Hz ÷
// (doubles per register) = how many register operations retire per cycle.
#define IMPACTID_CHAINS_12(op)                                                               \
  a0 = op(a0), a1 = op(a1), a2 = op(a2), a3 = op(a3), a4 = op(a4), a5 = op(a5), a6 = op(a6), \
  a7 = op(a7), a8 = op(a8), a9 = op(a9), a10 = op(a10), a11 = op(a11)
#define IMPACTID_CHAINS_16(op) \
  IMPACTID_CHAINS_12(op), a12 = op(a12), a13 = op(a13), a14 = op(a14), a15 = op(a15)

#pragma GCC diagnostic ignored "-Wpsabi"
struct Chains {
  double (*function)(long iterations, bool fused);
  int chains, lanes;  // flops per iteration: 2 · chains · lanes
};

#if defined(__x86_64__)
using Register8 = double __attribute__((vector_size(64)));
using Register4 = double __attribute__((vector_size(32)));
using Register2 = double __attribute__((vector_size(16)));

IMPACTID_AVX512_TARGET double chains_x86_64_v4(long iterations, bool fused) {
  const Register8 m = (Register8)_mm512_set1_pd(0.999999), c = (Register8)_mm512_set1_pd(1e-3);
  Register8 a0 = (Register8)_mm512_set1_pd(1.0), a1 = a0 + c, a2 = a1 + c, a3 = a2 + c, a4 = a3 + c,
            a5 = a4 + c, a6 = a5 + c, a7 = a6 + c, a8 = a7 + c, a9 = a8 + c, a10 = a9 + c,
            a11 = a10 + c, a12 = a11 + c, a13 = a12 + c, a14 = a13 + c, a15 = a14 + c;
  const auto fma = [&](Register8 a) IMPACTID_AVX512_TARGET __attribute__((always_inline)) {
    return (Register8)_mm512_fmadd_pd((__m512d)a, (__m512d)m, (__m512d)c);
  };
  const auto mul_add = [&](Register8 a) IMPACTID_AVX512_TARGET __attribute__((always_inline)) {
    return a * m + c;
  };
  if (fused) {
    for (long i = 0; i < iterations; ++i) IMPACTID_CHAINS_16(fma);
  } else {
    for (long i = 0; i < iterations; ++i) IMPACTID_CHAINS_16(mul_add);
  }
  const Register8 sum = ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7)) +
                        ((a8 + a9) + (a10 + a11)) + ((a12 + a13) + (a14 + a15));
  return sum[0];
}

IMPACTID_FMA_TARGET double chains_x86_64_v3(long iterations, bool fused) {
  const Register4 m = (Register4)_mm256_set1_pd(0.999999), c = (Register4)_mm256_set1_pd(1e-3);
  Register4 a0 = (Register4)_mm256_set1_pd(1.0), a1 = a0 + c, a2 = a1 + c, a3 = a2 + c, a4 = a3 + c,
            a5 = a4 + c, a6 = a5 + c, a7 = a6 + c, a8 = a7 + c, a9 = a8 + c, a10 = a9 + c,
            a11 = a10 + c;
  const auto fma = [&](Register4 a) IMPACTID_FMA_TARGET __attribute__((always_inline)) {
    return (Register4)_mm256_fmadd_pd((__m256d)a, (__m256d)m, (__m256d)c);
  };
  const auto mul_add = [&](Register4 a) IMPACTID_FMA_TARGET __attribute__((always_inline)) {
    return a * m + c;
  };
  if (fused) {
    for (long i = 0; i < iterations; ++i) IMPACTID_CHAINS_12(fma);
  } else {
    for (long i = 0; i < iterations; ++i) IMPACTID_CHAINS_12(mul_add);
  }
  const Register4 sum =
      ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7)) + ((a8 + a9) + (a10 + a11));
  return sum[0];
}

double chains_baseline(long iterations, bool /*fused: no instruction for it*/) {
  const Register2 m = {0.999999, 0.999999}, c = {1e-3, 1e-3};
  Register2 a0 = {1.0, 1.0}, a1 = a0 + c, a2 = a1 + c, a3 = a2 + c, a4 = a3 + c, a5 = a4 + c,
            a6 = a5 + c, a7 = a6 + c, a8 = a7 + c, a9 = a8 + c, a10 = a9 + c, a11 = a10 + c;
  const auto mul_add = [&](Register2 a) __attribute__((always_inline)) {
    return a * m + c;
  };
  for (long i = 0; i < iterations; ++i) IMPACTID_CHAINS_12(mul_add);
  const Register2 sum =
      ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7)) + ((a8 + a9) + (a10 + a11));
  return sum[0];
}

// The chains of the level that runs.
Chains level_chains() {
  switch (kernel_level()) {
    case KernelLevel::x86_64_v4:
      return {chains_x86_64_v4, 16, 8};
    case KernelLevel::x86_64_v3:
      return {chains_x86_64_v3, 12, 4};
    case KernelLevel::baseline:
      break;
  }
  return {chains_baseline, 12, 2};
}
#endif

// flops/s of the level's chains (level_chains above), with a separate multiply and add or fused.
void measure_peak(benchmark::State& state, bool fused) {
#if defined(__x86_64__)
  constexpr long kIterations = 1'000'000;
  const Chains chains = level_chains();
  for (auto _ : state) benchmark::DoNotOptimize(chains.function(kIterations, fused));
  state.counters["flops/s"] = benchmark::Counter(
      2.0 * chains.chains * chains.lanes * kIterations * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
  state.SetLabel(to_string(kernel_level()));
#else
  state.SkipWithError("x86-64 only");
#endif
}
void BM_MulAddPeak(benchmark::State& state) {
  measure_peak(state, false);
}
BENCHMARK(BM_MulAddPeak)->Unit(benchmark::kMillisecond);
void BM_FmaPeak(benchmark::State& state) {
  measure_peak(state, true);
}
BENCHMARK(BM_FmaPeak)->Unit(benchmark::kMillisecond);

// The memory bandwidth bound of a roofline beside BM_FmaPeak's flops bound: STREAM's triad
// a = b + s·c (McCalpin) on arrays of range(0) doubles each, which for the default sizes are far
// larger than the last-level cache. bytes/s counts STREAM's way, 3 × 8 bytes per element (the
// write-allocate read of `a` the processor may add is not counted), so that the figure compares
// with published STREAM results. One thread, as one point of a model sweep runs.
void BM_StreamTriad(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const double scalar = 3.0;
  for (auto _ : state) {
    double* out = a.data();
    const double* x = b.data();
    const double* y = c.data();
    for (std::size_t i = 0; i < n; ++i) out[i] = x[i] + scalar * y[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  // Every element written by every iteration: a wrong loop would not leave 7 everywhere.
  if (std::any_of(a.begin(), a.end(), [](double v) { return v != 7.0; })) {
    state.SkipWithError("the triad did not write b + 3·c");
    return;
  }
  state.counters["bytes/s"] =
      benchmark::Counter(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.SetLabel(std::to_string(24 * n / (1 << 20)) + " MiB streamed per iteration");
}
// 2^22 doubles (32 MiB) per array: 96 MiB in all, past any last-level cache of the machines
// CI may get.
BENCHMARK(BM_StreamTriad)->Arg(1 << 22)->Unit(benchmark::kMillisecond);

// The general sparse reference (SparseLU every step), checked to give the same pressures.
void BM_SparseReference(benchmark::State& state) {
  const RodScene scene;
  const HhtParams hht{};
  SimulationWorkspace workspace;
  simulate(scene, hht, RunOptions{}, workspace);
  const std::vector<double> reference = sparse_reference_pressure(scene, hht);
  double worst = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    worst = std::max(worst, std::abs(reference[i] - workspace.trace.pressure[i]));
  }
  if (!(worst <= 1e-9 * derive(scene).pressure_scale)) {
    state.SkipWithError("the sparse reference disagrees with the kernel");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(sparse_reference_pressure(scene, hht));
  state.SetLabel("hht, SparseLU refactorised every step");
  state.counters["max_pressure_difference"] = worst;
  set_dof_counters(state, scene, static_cast<double>(state.iterations()));
}
BENCHMARK(BM_SparseReference)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace impactid

// Google Benchmark's main, with the kernels that run and what the processor supports in the
// context every report starts with (bench/report prints it; a speed figure means little without
// it).
int main(int argc, char** argv) {
  const impactid::KernelSelection& kernels = impactid::kernel_selection();
  if (!kernels.error.empty()) {
    std::fprintf(stderr, "impactid_bench: %s\n", kernels.error.c_str());
    return 2;
  }
  benchmark::AddCustomContext("impactid_kernels", impactid::to_string(kernels.level));
  benchmark::AddCustomContext("impactid_kernels_supported", impactid::to_string(kernels.supported));
  benchmark::AddCustomContext("impactid_kernels_forced", kernels.forced ? "yes" : "no");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
