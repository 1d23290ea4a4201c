// The system interface (core/model/semi_discrete_system.hpp) and the one dispatch of simulate()
// over it (core/run/steppers.hpp): both systems model the concept, a type without the
// factorisation does not, and the paper's rod run as a user's sparse model goes through the same
// method dispatch with the same numbers as the rod's tridiagonal system, method by method.
#include "core/model/semi_discrete_system.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <variant>

#include "core/methods/method_registry.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/sparse_system.hpp"
#include "core/run/simulation.hpp"
#include "core/run/steppers.hpp"

namespace impactid {
namespace {

static_assert(SemiDiscreteSystem<SecondOrderSystem>);
static_assert(SemiDiscreteSystem<SparseSystem>);

// A system without a factorisation (and without the products) is not a system a stepper runs on.
struct MatricesOnly {
  using Matrix = Eigen::MatrixXd;
  Eigen::MatrixXd mass, damping, stiffness;
  Eigen::Index size() const { return mass.rows(); }
};
static_assert(!SemiDiscreteSystem<MatricesOnly>);
static_assert(!SemiDiscreteSystem<Tridiagonal>);

// The workspace's steppers are chosen by the system's type.
static_assert(std::is_same_v<decltype(std::declval<SimulationWorkspace&>().steppers<SparseSystem>()),
                             Steppers<SparseSystem>&>);
static_assert(
    std::is_same_v<decltype(std::declval<SimulationWorkspace&>().steppers<SecondOrderSystem>()),
                   Steppers<SecondOrderSystem>&>);

// The rod's assembled scene, as the tridiagonal system with its named wall and as a sparse model
// with the same matrices and the wall as a listed constraint. Their steppers differ (Thomas
// against LDLᵀ solves, the wall's O(1) correction against a solve) by round-off, and which of two
// round-off-close predictions penetrates decides a step's multiplier, so the runs are compared
// over the impact's first steps, as tests/sparse_model_test.cpp compares the integrators.
struct RodTwice {
  AssembledScene tridiagonal, sparse;
  double pressure_scale = 0.0, velocity = 0.0;
};

RodTwice rod_twice() {
  RodScene rod;
  rod.elements = 100;
  const RodSceneDerived d = derive(rod);
  RodTwice twice;
  twice.pressure_scale = d.pressure_scale;
  twice.velocity = rod.velocity;
  twice.tridiagonal = assemble(rod);
  twice.tridiagonal.step_count = static_cast<long>(d.impact_time / d.time_step) + 40;
  twice.sparse = twice.tridiagonal;
  const SecondOrderSystem& tri = twice.tridiagonal.system;
  auto sparse = std::make_shared<SparseSystem>();
  sparse->mass = to_sparse(tri.mass);
  sparse->stiffness = to_sparse(tri.stiffness);
  sparse->damping = to_sparse(tri.damping);
  sparse->constraints = {{tri.contact_dof, -1, tri.gap}};
  twice.sparse.sparse = sparse;
  twice.sparse.contact_columns = true;  // a listed scene records every contact's columns
  return twice;
}

TEST(SemiDiscreteSystem, EveryMethodRunsTheRodAsASparseModelAsOnItsTridiagonalSystem) {
  const RodTwice rod = rod_twice();
  SimulationWorkspace tri_ws, sparse_ws;
  for (const MethodDescriptor& m : method_registry()) {
    const auto built = build_method(m.kind, {});
    ASSERT_TRUE(std::holds_alternative<MethodParams>(built)) << m.name;
    const MethodParams& method = std::get<MethodParams>(built);
    // A loose energy bound: Lagrange contact makes some defaults chatter on the rod (Wilson-θ's
    // energy passes 1.5 times the initial), which is not this test's subject.
    const RunOptions options{.energy_growth_limit = 1e3};
    const RunSummary a = simulate(rod.tridiagonal, method, options, tri_ws);
    const RunSummary b = simulate(rod.sparse, method, options, sparse_ws);
    ASSERT_EQ(a.status, RunStatus::ok) << m.name << ": " << a.message;
    ASSERT_EQ(b.status, RunStatus::ok) << m.name << ": " << b.message;
    EXPECT_EQ(a.steps, b.steps) << m.name;
    EXPECT_EQ(a.skipped_steps, b.skipped_steps) << m.name;
    double worst_pressure = 0.0, worst_velocity = 0.0, largest_pressure = 0.0;
    for (std::size_t i = 0; i < tri_ws.trace.pressure.size(); ++i) {
      worst_pressure =
          std::max(worst_pressure, std::abs(tri_ws.trace.pressure[i] - sparse_ws.trace.pressure[i]));
      worst_velocity =
          std::max(worst_velocity, std::abs(tri_ws.trace.velocity[i] - sparse_ws.trace.velocity[i]));
      largest_pressure = std::max(largest_pressure, tri_ws.trace.pressure[i]);
    }
    // The impact happened within the compared samples, and both runs saw the same one.
    EXPECT_GT(largest_pressure, 0.1 * rod.pressure_scale) << m.name;
    EXPECT_LT(worst_pressure, 1e-6 * rod.pressure_scale) << m.name;
    EXPECT_LT(worst_velocity, 1e-6 * rod.velocity) << m.name;
  }
}

}  // namespace
}  // namespace impactid
