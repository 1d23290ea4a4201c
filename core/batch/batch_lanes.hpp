// The per-lane bookkeeping of the rod's batched kernels (core/batch/rod_kernel.cpp: the implicit
// and composite steps; core/batch/explicit_kernel.cpp: the explicit methods), apart from their
// steps: each lane's set-up as simulate() does it (summary, trace, state at t = 0, the filled-in
// free flight), the run loop of run_steps (core/run/simulation.cpp) over every lane of a batch at
// once, and the end (the samples a lane did not reach are NaN, the wall time shared).
//
// A kernel supplies its step as a lane stepper (run_lanes below says what it offers), so that
// every kernel stops, checks and records its lanes exactly as simulate() does, and each kernel's
// file holds only its arithmetic.
//
// Internal to core/: included by the kernels' files only, after core/batch/kernel_target.hpp (it
// lives in the level's namespace, as core/batch/simd_lanes.hpp). Everything the loop calls is
// inlined into the kernel.
//
// Thread safety: values and pure functions; each batch its own objects.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <span>
#include <vector>

#include "core/batch/simd_lanes.hpp"
#include "core/common/run_record.hpp"
#include "core/common/state.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/second_order_system.hpp"
#include "core/run/simulation.hpp"

namespace impactid::simd {
inline namespace IMPACTID_KERNEL_NAMESPACE {

// The samples of the contact pressure and velocity of every lane, [sample][lane] as the step
// gives them, written into the lanes' traces (one vector per lane) a chunk at a time. Written
// sample by sample, the 2·kBatchLanes scattered stores and the lane loop around them took a
// share of the batch's time worth saving (the figure is in the git log).
constexpr long kTraceChunk = 32;
struct TraceChunk {
  Lanes pressure[kTraceChunk], velocity[kTraceChunk];
  long begin = 0;  // the sample held in slot 0

  // Writes samples [begin, through] into the traces of the lanes stepping now (which stepped
  // at every one of them: a lane starts or stops only at an event, and events flush first).
  void flush(std::array<LaneRun, kLanes>& lanes, long through) {
    if (through >= begin) {
      for (int l = 0; l < kLanes; ++l) {
        LaneRun& run = lanes[static_cast<std::size_t>(l)];
        if (!run.stepping) continue;
        double* p = run.trace->pressure.data();
        double* v = run.trace->velocity.data();
        for (long i = begin; i <= through; ++i) {
          p[i] = pressure[i - begin][l];
          v[i] = velocity[i - begin][l];
        }
        run.summary->steps = through + 1;
      }
    }
    begin = through + 1;
  }
};

// The batch's share of run_steps' options, and the rod's contact area (pressure = λ/A).
struct LaneLoop {
  double area;
  double dt;
  int energy_check_interval;
  double energy_growth_limit;
};

// The batch's loop settings for lanes of one rod and time step (scene: the batch's first).
inline LaneLoop loop_settings(const RodScene& scene, const RunOptions& options) {
  return {.area = scene.area,
          .dt = derive(scene).time_step,
          .energy_check_interval = options.energy_check_interval,
          .energy_growth_limit = options.energy_growth_limit};
}

// A kernel's [unknown][lane] arrays, `count` arrays of n rows each, zeroed, in a workspace's
// storage (kept between batches, so that a thread allocates once): each kernel takes its arrays
// one after the other. Taking more than `count` is a bug (asserted).
class LaneStorage {
 public:
  LaneStorage(std::vector<LaneBlock>& storage, int count, Eigen::Index n) : n_(n), left_(count) {
    storage.assign(static_cast<std::size_t>(count * n), LaneBlock{});
    next_ = reinterpret_cast<Lanes*>(storage.data());
  }

  // The next array of n rows.
  Lanes* take() {
    assert(left_ > 0);
    --left_;
    Lanes* array = next_;
    next_ += n_;
    return array;
  }
  // The next arrays, one for each pointer, in order.
  void take(std::initializer_list<Lanes**> arrays) {
    for (Lanes** array : arrays) *array = take();
  }

 private:
  Lanes* next_;
  Eigen::Index n_;
  int left_;
};

// Where a lane starts stepping: its λ and t there (simulate()'s state after the free flight).
struct LaneStart {
  double lambda;
  double t;
};

// The step of a kernel, as run_lanes calls it: five callables (lambdas, so that every call is
// inlined), made by lane_stepper().
//   start(l) -> LaneStart     writes lane l's start state into the kernel's arrays
//   step(starting, λ) -> Lanes  advances every lane one sample (λ at t in, λ at t + Δt out);
//                             `starting`: some lane was started just before this step
//   velocity() -> Lanes       every lane's contact-node velocity at the sample just computed
//   energy() -> Lanes         every lane's energy at that sample (the method's own: RunOptions)
//   stop(l)                   zeroes lane l (stopped lanes step zeros, at no risk)
template <class Start, class Step, class Velocity, class Energy, class Stop>
struct LaneStepper {
  Start start;
  Step step;
  Velocity velocity;
  Energy energy;
  Stop stop;
};
// A function rather than deduction guides: clang 14 does not deduce an aggregate's arguments.
template <class Start, class Step, class Velocity, class Energy, class Stop>
[[gnu::always_inline]] inline LaneStepper<Start, Step, Velocity, Energy, Stop> lane_stepper(
    Start start, Step step, Velocity velocity, Energy energy, Stop stop) {
  return {start, step, velocity, energy, stop};
}

// run_steps (core/run/simulation.cpp) for every lane of a batch: the samples from the first lane's
// start to the last lane's end. A lane that is not stepping (before its free flight ends, after
// its last sample or its instability, a failed or unused lane) holds a zero state (stop), which
// a step maps to zero: it costs lanes, never correctness.
//
// run_steps' bookkeeping happens lane by lane only at events: a lane starting, a lane's energy
// check or last sample, a non-finite λ or velocity in some lane. Between events the loop only
// steps, advances every lane's t (as run_steps' state.t += Δt) and buffers the trace.
template <class Stepper>
[[gnu::always_inline]] inline void run_lanes(std::array<LaneRun, kLanes>& lanes,
                                             const LaneLoop& loop, Stepper&& stepper) {
  const auto [begin, end] = lane_samples(lanes);
  TraceChunk chunk;
  chunk.begin = begin;
  Lanes lambda{}, t{};
  long event = next_lane_event(lanes, begin);
  for (long i = begin; i <= end; ++i) {
    const bool at_event = i == event;
    bool starting = false;
    if (at_event) {
      chunk.flush(lanes, i - 1);
      for (int l = 0; l < kLanes; ++l) {
        LaneRun& run = lanes[static_cast<std::size_t>(l)];
        if (run.first != i || run.first > run.last) continue;
        const LaneStart start = stepper.start(l);
        starting = true;
        lambda.set(l, start.lambda);
        t.set(l, start.t);
        run.next_check = run.first - 1 + loop.energy_check_interval;
        run.stepping = true;
      }
    }
    lambda = stepper.step(starting, lambda);
    t = t + splat(loop.dt);
    const Lanes velocity = stepper.velocity();
    const long slot = i - chunk.begin;
    // λ/A of every lane in two vector divides rather than kBatchLanes scalar ones.
    store(&chunk.pressure[slot], lambda / splat(loop.area));
    store(&chunk.velocity[slot], velocity);
    if (!at_event && all_finite(lambda, velocity)) {
      if (slot + 1 == kTraceChunk) chunk.flush(lanes, i);
      continue;
    }
    chunk.flush(lanes, i);

    // run_steps' checks, lane by lane; the energy (two O(n) products) only when a lane checks
    // it at this sample, for every lane at once.
    Lanes energy{};
    if (energy_due(lanes, i)) energy = stepper.energy();
    for (int l = 0; l < kLanes; ++l) {
      LaneRun& run = lanes[static_cast<std::size_t>(l)];
      if (!run.stepping) continue;
      check_lane_energy(run, i, energy[l], t[l], loop.energy_check_interval,
                        loop.energy_growth_limit);
      if (run.stepping && (!std::isfinite(lambda[l]) || !std::isfinite(velocity[l]))) {
        stop_unstable(run, "non-finite values at t = " + format_value(t[l]) + " s");
      }
      if (run.stepping && i == run.last) run.stepping = false;
      if (!run.stepping) {
        stepper.stop(l);
        lambda.set(l, 0.0);
      }
    }
    event = next_lane_event(lanes, i + 1);
    // No lane steps or starts any more (all ended, unstable or failed): the rest would step zeros.
    // A batch of unstable points then ends at its last lane's instability rather than at its end
    // time (docs/performance.md).
    if (event == std::numeric_limits<long>::max()) break;
  }
}

// simulate()'s set-up of lane l of a batch of rod scenes (prepare_run, for the rod): the
// summary and the trace (pressure and velocity only: no histories), the state at t = 0 with its
// consistent acceleration, the free flight filled in and the state moved to its end in
// starts[l], and the lane's LaneRun (its first and last sample, its energy bound). Returns false
// with the summary `failed` when the run options are invalid (the lane then does not run).
// `system` is the rod (every lane's but for the gap); lanes of one velocity share the
// acceleration and the energy at t = 0 of the first of them (bit for bit the same), so lanes
// are prepared in order, and a kernel whose start changes a lane's start state (a contact at
// the start) prepares every lane before it changes any.
inline bool prepare_lane(const SecondOrderSystem& system, std::span<const RodScene> scenes, int l,
                         const RunOptions& options, double dt, std::span<RunSummary> summaries,
                         LaneSpan<ContactTrace> traces, LaneSpan<State> starts, LaneRun& run) {
  const auto lane = static_cast<std::size_t>(l);
  const Eigen::Index n = system.size();
  const RodScene& scene = scenes[lane];
  const RodSceneDerived derived = derive(scene);
  RunSummary& summary = summaries[lane];
  summary = RunSummary{};
  summary.planned_steps = derived.step_count;
  summary.dt = dt;
  ContactTrace& trace = traces[lane];
  const auto samples = static_cast<std::size_t>(derived.step_count);
  // NaN from the lane's last computed sample on is filled in after the run (finish_lanes: the
  // samples before it are all written): filling the whole trace first wrote each trace twice.
  trace.pressure.resize(samples);
  trace.velocity.resize(samples);
  trace.displacement.clear();
  trace.energy.clear();
  trace.far_pressure.clear();
  if (options.energy_check_interval < 1 || !(options.energy_growth_limit > 1.0)) {
    summary.status = RunStatus::failed;
    summary.message = "run options: energy_check_interval must be >= 1 and energy_growth_limit > 1";
    return false;
  }

  // The state at t = 0, then the filled-in free flight: simulate()'s set-up.
  State& state = starts[lane];
  state.u.setZero(n);
  state.v.setConstant(n, scene.velocity);
  state.lambda = state.far_lambda = state.t = 0.0;
  // M·a = −K·u − C·v at u = 0 depends on the lane only through v0: lanes of one velocity
  // (a sweep's usual case) share one solve, bit for bit the same.
  int same_velocity = -1;
  for (int earlier = 0; earlier < l && same_velocity < 0; ++earlier) {
    if (scenes[static_cast<std::size_t>(earlier)].velocity == scene.velocity) {
      same_velocity = earlier;
    }
  }
  // So does the energy ½vᵀMv + ½uᵀKu at u = 0.
  if (same_velocity < 0) {
    state.a = consistent_acceleration(system, state);
    summary.initial_energy = system.energy(state.u, state.v);
  } else {
    state.a = starts[static_cast<std::size_t>(same_velocity)].a;
    summary.initial_energy = summaries[static_cast<std::size_t>(same_velocity)].initial_energy;
  }
  summary.final_energy = summary.initial_energy;
  const long skipped = free_flight_samples(derived.impact_time, dt, derived.step_count,
                                           scene.rayleigh_mass == 0.0, options);
  std::fill_n(trace.pressure.begin(), skipped, 0.0);
  std::fill_n(trace.velocity.begin(), skipped, scene.velocity);
  if (skipped > 0) {
    state.t = skipped * dt;
    state.u.setConstant(n, scene.velocity * state.t);
  }
  summary.steps = summary.skipped_steps = skipped;

  run.summary = &summary;
  run.trace = &trace;
  run.first = skipped;
  run.last = derived.step_count - 1;
  run.energy_bound = options.energy_growth_limit * summary.initial_energy;
  return true;
}

// The end of a batch of `count` lanes: the samples a lane did not reach are NaN (as simulate()
// leaves them), and each lane's wall time is the batch's divided by the lanes.
inline void finish_lanes(int count, std::chrono::steady_clock::time_point start,
                         LaneSpan<ContactTrace> traces, std::span<RunSummary> summaries) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (int l = 0; l < count; ++l) {
    ContactTrace& trace = traces[static_cast<std::size_t>(l)];
    const long steps = summaries[static_cast<std::size_t>(l)].steps;  // samples [0, steps) written
    std::fill(trace.pressure.begin() + steps, trace.pressure.end(), kNaN);
    std::fill(trace.velocity.begin() + steps, trace.velocity.end(), kNaN);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int l = 0; l < count; ++l)
    summaries[static_cast<std::size_t>(l)].wall_time_s = seconds / count;
}

}  // namespace IMPACTID_KERNEL_NAMESPACE
}  // namespace impactid::simd
