// Run time of a user's model (issue 20) as its size grows, and the sparse factorisation against
// CHOLMOD's. The model is a square grid of bilinear (Q1) elements, one DOF per node (the
// stiffness of a membrane: the sparsity and fill-in of a 2D mesh), with a lumped mass, dropped
// onto a rigid wall along 41 nodes of one edge, as the shipped block (examples/block). Sizes
// 32², 100² and 316² nodes: about 1e3, 1e4 and 1e5 DOFs (runs on the first two, every registered
// method); the factorisations are timed on all three and on the block itself (argument 0).
// Counter `steps/s`: of a run of 200 steps with contact from step 100 on, set-up included.
#include <benchmark/benchmark.h>

#include <Eigen/SparseCholesky>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "core/batch/batched_model.hpp"
#include "core/batch/sparse_lanes.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/run/simulation.hpp"
#include "study/plan/plan.hpp"
#include "tests/grid_model.hpp"
#include "study/plan/simulation_settings.hpp"

#ifdef IMPACTID_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace impactid {
namespace {

constexpr long kSteps = 200;

// The grid model of side × side nodes: Q1 membrane stiffness (E = 1 per element), unit
// lumped mass per element shared by its nodes, every node at v = −1 toward the wall, 41 wall
// contacts (u >= −gap) spread over the first row, closing at step 100.
std::shared_ptr<const Model> grid_model(int side) {
  const std::shared_ptr<Model> model = testing::grid_membrane(side);
  const double dt = 1.0 / model->omega_bound;  // Courant 0.5
  for (int c = 0; c < 41; ++c) {
    const Eigen::Index dof = static_cast<Eigen::Index>(c) * (side - 1) / 40;
    // Appended, not "c" + to_string(c): GCC 12 warns falsely (-Wrestrict) on that operator+.
    std::string name = "c";
    name += std::to_string(c);
    model->contacts.push_back({name, -1, dof, 100.0 * dt, 1.0, dof});
  }
  return model;
}

ModelScene grid_scene(int side) {
  const std::shared_ptr<const Model> model = grid_model(side);
  const double dt = 1.0 / model->omega_bound;
  return {model, dt, static_cast<double>(kSteps) * dt};
}

// One run (set-up and 200 steps) of each registered method with its defaults. Args: the grid's
// side, the method's index in method_registry(), so a new method is timed without a line here.
// Counter steps/s over the steps the run took: a method whose defaults go unstable on a grid
// (Bathe's and Wilson-θ's on the 100² one) stops there, as a sweep point would, and its label
// says at which step; a run that cannot start (status failed) is an error. The grids of 32² and
// 100² nodes only: on the 1e5-DOF grid an implicit method's run is its factorisation and 200
// solves, which BM_SparseFactor/316 and BM_SparseSolve/316 time, and the registry's methods took
// minutes there together, too long for bench.every_benchmark_once, which runs every case.
void BM_ModelRun(benchmark::State& state) {
  const ModelScene scene = grid_scene(static_cast<int>(state.range(0)));
  const AssembledScene assembled = assemble(scene);
  const MethodDescriptor& descriptor = method_registry()[static_cast<std::size_t>(state.range(1))];
  const MethodParams method = std::get<MethodParams>(descriptor.make(MethodArguments{}));
  std::string label =
      std::string(descriptor.name) + ", " + std::to_string(scene.model->size()) + " DOFs";
  SimulationWorkspace workspace;
  double steps = 0.0;
  for (auto _ : state) {
    const RunSummary s = simulate(assembled, method, RunOptions{}, workspace);
    if (s.status == RunStatus::failed) state.SkipWithError(s.message.c_str());
    if (s.status == RunStatus::unstable && steps == 0.0) {
      label += ", unstable at step " + std::to_string(s.steps);
    }
    steps += static_cast<double>(s.steps);
    benchmark::DoNotOptimize(s.final_energy);
  }
  state.SetLabel(label);
  state.counters["steps/s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ModelRun)
    ->ArgsProduct({{32, 100},
                   benchmark::CreateDenseRange(0, static_cast<int>(method_registry().size()) - 1,
                                               1)})
    ->Unit(benchmark::kMillisecond);

// Central difference on a model, kBatchLanes consecutive points of a Courant sweep (0.50 to 0.575
// in steps of 0.005, as a batch of a fine sweep holds; a batch runs until its longest lane
// ends, so its lanes' spread of step counts, here 15 %, is time no lane uses): each point
// alone through simulate() (Each) and all together through the model kernel (Lanes,
// core/batch/batched_model.hpp), the same numbers bit for bit. Args: the grid's side (0: the
// shipped block). Counter points/s, set-up included; the ratio of the two is the issue's "per
// point" speed-up of an explicit sweep.
std::vector<AssembledScene> courant_sweep(int side) {
  const ModelScene base =
      side > 0
          ? grid_scene(side)
          : *std::get<Simulation>(build(load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) /
                                                        "examples/block/scene.toml")))
                 .model();
  std::vector<AssembledScene> scenes;
  for (int k = 0; k < kBatchLanes; ++k) {
    ModelScene scene = base;
    const double courant = 0.5 + 0.005 * k;
    scene.dt = 2.0 * courant / base.model->omega_bound;
    scene.t_end = static_cast<double>(kSteps) * (2.0 * 0.6 / base.model->omega_bound);
    scenes.push_back(assemble(scene));
  }
  return scenes;
}

void BM_ModelSweepEach(benchmark::State& state) {
  const std::vector<AssembledScene> scenes = courant_sweep(static_cast<int>(state.range(0)));
  SimulationWorkspace workspace;
  for (auto _ : state) {
    for (const AssembledScene& scene : scenes) {
      benchmark::DoNotOptimize(
          simulate(scene, CentralDifferenceParams{}, RunOptions{}, workspace).final_energy);
    }
  }
  state.counters["points/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * kBatchLanes, benchmark::Counter::kIsRate);
  state.SetLabel(std::to_string(scenes[0].sparse->size()) + " DOFs");
}
BENCHMARK(BM_ModelSweepEach)->Arg(0)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);

void BM_ModelSweepLanes(benchmark::State& state) {
  const std::vector<AssembledScene> scenes = courant_sweep(static_cast<int>(state.range(0)));
  std::vector<const AssembledScene*> pointers;
  for (const AssembledScene& scene : scenes) pointers.push_back(&scene);
  const std::vector<MethodParams> methods(scenes.size(), CentralDifferenceParams{});
  std::vector<RunSummary> summaries(scenes.size());
  ModelBatchWorkspace workspace;
  for (auto _ : state) {
    simulate_model_batch(pointers, methods, RunOptions{}, workspace, summaries);
    benchmark::DoNotOptimize(summaries[0].final_energy);
  }
  state.counters["points/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * kBatchLanes, benchmark::Counter::kIsRate);
  state.SetLabel(std::to_string(scenes[0].sparse->size()) + " DOFs, " +
                 std::to_string(workspace.kernel_lanes()) + " lanes in the kernel");
}
BENCHMARK(BM_ModelSweepLanes)->Arg(0)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);

// HHT's effective matrix of the grid model, M + b1·dt²·K; side 0: of the shipped block
// (examples/block, 1722 DOFs of plane strain).
SparseMatrix effective_matrix(int side) {
  const ModelScene scene =
      side > 0
          ? grid_scene(side)
          : *std::get<Simulation>(build(load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) /
                                                        "examples/block/scene.toml")))
                 .model();
  const ImplicitCoefficients c = implicit_coefficients(HhtParams{.alpha = -0.1});
  const double dt = scene.dt;
  return SparseMatrix((1.0 - c.alpha_m) * scene.model->mass +
                      (1.0 - c.alpha_f) * c.b1 * dt * dt * scene.model->stiffness);
}

// One solve with the factor: what a step costs (a step makes one, two in contact).
void BM_SparseSolve(benchmark::State& state) {
  const SparseMatrix a = effective_matrix(static_cast<int>(state.range(0)));
  SparseFactorization f;
  if (!f.factor(a)) state.SkipWithError("factorisation failed");
  Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  for (auto _ : state) {
    f.solve_in_place(b);
    benchmark::DoNotOptimize(b.data());
  }
  state.SetLabel("SimplicialLDLT/AMD, nnz(L) = " + std::to_string(f.factor_nonzeros()));
}
BENCHMARK(BM_SparseSolve)->Arg(0)->Arg(32)->Arg(100)->Arg(316)->Unit(benchmark::kMicrosecond);

void BM_SparseFactor(benchmark::State& state) {
  const SparseMatrix a = effective_matrix(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    SparseFactorization f;
    benchmark::DoNotOptimize(f.factor(a));
  }
  state.SetLabel("SimplicialLDLT/AMD");
}
BENCHMARK(BM_SparseFactor)->Arg(0)->Arg(32)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);

// The stiffness product K·u of an explicit step for a batch of kBatchLanes points: as each
// point alone (kBatchLanes calls of multiply_add, each reading K once) and in lanes
// (multiply_add_lanes: K read once for all; core/batch/sparse_lanes.hpp). Same K as the runs':
// the grid model's (side 32, 100, 316) or the block's (0). Counters: lane products per second,
// and the bytes of K (values and row indices) read per lane product.
SparseMatrix product_stiffness(int side) {
  return side > 0 ? grid_scene(side).model->stiffness
                  : std::get<Simulation>(
                        build(load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) /
                                              "examples/block/scene.toml")))
                        .model()
                        ->model->stiffness;
}

std::vector<LaneBlock> product_lanes(Eigen::Index n) {
  std::vector<LaneBlock> x(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int l = 0; l < kBatchLanes; ++l) {
      x[static_cast<std::size_t>(i)].lane[l] = 1.0 + 1e-3 * static_cast<double>((i + l) % 97);
    }
  }
  return x;
}

void product_counters(benchmark::State& state, const SparseMatrix& k) {
  const double products = static_cast<double>(state.iterations()) * kBatchLanes;
  state.counters["lane-products/s"] = benchmark::Counter(products, benchmark::Counter::kIsRate);
  state.counters["K bytes/lane"] =
      static_cast<double>(k.nonZeros()) * (sizeof(double) + sizeof(int));
  state.SetLabel(std::to_string(k.rows()) + " DOFs, " + std::to_string(k.nonZeros()) + " nnz");
}

void BM_StiffnessProductEach(benchmark::State& state) {
  const SparseMatrix k = product_stiffness(static_cast<int>(state.range(0)));
  std::vector<Eigen::VectorXd> x(kBatchLanes, Eigen::VectorXd::Ones(k.rows()));
  std::vector<Eigen::VectorXd> y(kBatchLanes, Eigen::VectorXd::Zero(k.rows()));
  for (auto _ : state) {
    for (int l = 0; l < kBatchLanes; ++l) multiply_add(k, -1.0, x[l], y[l]);
    benchmark::DoNotOptimize(y.data());
  }
  product_counters(state, k);
}
BENCHMARK(BM_StiffnessProductEach)->Arg(0)->Arg(100)->Arg(316)->Unit(benchmark::kMicrosecond);

void BM_StiffnessProductLanes(benchmark::State& state) {
  const SparseMatrix k = product_stiffness(static_cast<int>(state.range(0)));
  const std::vector<LaneBlock> x = product_lanes(k.rows());
  std::vector<LaneBlock> y(static_cast<std::size_t>(k.rows()));
  for (auto _ : state) {
    multiply_add_lanes(k, -1.0, x, y);
    benchmark::DoNotOptimize(y.data());
  }
  product_counters(state, k);
  state.counters["K bytes/lane"] = state.counters["K bytes/lane"] / kBatchLanes;
}
BENCHMARK(BM_StiffnessProductLanes)->Arg(0)->Arg(100)->Arg(316)->Unit(benchmark::kMicrosecond);

#ifdef IMPACTID_HAVE_CHOLMOD
// The same with CHOLMOD's supernodal Cholesky (Debian's SuiteSparse), through Eigen's wrapper.
void BM_CholmodSolve(benchmark::State& state) {
  const SparseMatrix a = effective_matrix(static_cast<int>(state.range(0)));
  Eigen::CholmodSupernodalLLT<SparseMatrix> f(a);
  if (f.info() != Eigen::Success) state.SkipWithError("factorisation failed");
  Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows()), x(a.rows());
  for (auto _ : state) {
    x = f.solve(b);
    benchmark::DoNotOptimize(x.data());
  }
  state.SetLabel("CHOLMOD supernodal");
}
BENCHMARK(BM_CholmodSolve)->Arg(0)->Arg(32)->Arg(100)->Arg(316)->Unit(benchmark::kMicrosecond);

void BM_CholmodFactor(benchmark::State& state) {
  const SparseMatrix a = effective_matrix(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Eigen::CholmodSupernodalLLT<SparseMatrix> f(a);
    benchmark::DoNotOptimize(f.info());
  }
  state.SetLabel("CHOLMOD supernodal");
}
BENCHMARK(BM_CholmodFactor)->Arg(0)->Arg(32)->Arg(100)->Arg(316)->Unit(benchmark::kMillisecond);
#endif

}  // namespace
}  // namespace impactid
