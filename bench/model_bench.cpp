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

#include "core/methods/method_registry.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/run/simulation.hpp"
#include "study/plan/plan.hpp"
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
  const int n = side * side;
  const double ke[4][4] = {{4, -1, -2, -1}, {-1, 4, -1, -2}, {-2, -1, 4, -1}, {-1, -2, -1, 4}};
  std::vector<Eigen::Triplet<double>> k, m;
  for (int i = 0; i + 1 < side; ++i) {
    for (int j = 0; j + 1 < side; ++j) {
      const int nodes[4] = {i * side + j, i * side + j + 1, (i + 1) * side + j + 1,
                            (i + 1) * side + j};
      for (int a = 0; a < 4; ++a) {
        m.emplace_back(nodes[a], nodes[a], 0.25);
        for (int b = 0; b < 4; ++b) k.emplace_back(nodes[a], nodes[b], ke[a][b] / 6.0);
      }
    }
  }
  auto model = std::make_shared<Model>();
  model->mass.resize(n, n);
  model->mass.setFromTriplets(m.begin(), m.end());
  model->stiffness.resize(n, n);
  model->stiffness.setFromTriplets(k.begin(), k.end());
  model->initial_displacement = Eigen::VectorXd::Zero(n);
  model->initial_velocity = Eigen::VectorXd::Constant(n, -1.0);
  model->omega_bound = gershgorin_omega(model->mass, model->stiffness);
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
