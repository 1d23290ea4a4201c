// Newmark (eqs 11–13): energy conservation of the trapezoidal rule, the identity of δ = 1 with
// backward Euler, and the equivalence of the δ form and the explicit (β, γ) form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/methods/implicit_integrator.hpp"
#include "core/methods/method.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::make_state;
using testing::max_abs_difference;
using testing::run;

// The paper's rod (n = 200, default Δt) without a wall, with a smooth stressed and moving profile.
struct FreeVibration {
  SecondOrderSystem system;
  double dt;
  State initial;
};
FreeVibration free_vibration() {
  const RodScene scene;
  SecondOrderSystem system = assemble_rod(scene);
  system.gap = std::numeric_limits<double>::infinity();
  const Eigen::Index n = system.size();
  Eigen::VectorXd u(n), v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = static_cast<double>(i) / (n - 1);
    u[i] = 1e-3 * std::cos(std::numbers::pi * x) + 4e-4 * x * x * x;
    v[i] = 200.0 * std::sin(3.0 * std::numbers::pi * x);
  }
  return {system, derive(scene).time_step, make_state(u, v)};
}

// δ = 0 (trapezoidal rule) conserves ½vᵀMv + ½uᵀKu exactly for a linear undamped system; any
// drift would be numerical damping or growth the paper's comparison does not allow for.
TEST(Newmark, TrapezoidalRuleConservesEnergy) {
  FreeVibration p = free_vibration();
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(p.system, implicit_coefficients(NewmarkParams{.delta = 0.0}),
                                    p.dt));
  State s = p.initial;
  s.a = consistent_acceleration(p.system, s);
  const double e0 = p.system.energy(s.u, s.v);
  ASSERT_GT(e0, 0.0);
  double worst = 0.0;
  for (int i = 0; i < 3000; ++i) {  // ~3.5 transits of the wave along the rod
    integrator.step(p.system, s);
    worst = std::max(worst, std::abs(p.system.energy(s.u, s.v) - e0) / e0);
  }
  EXPECT_LT(worst, 1e-12);
  // It really vibrated: the displacement field changed substantially.
  EXPECT_GT((s.u - p.initial.u).norm(), 0.1 * p.initial.u.norm());
}

// Control for the test above: δ > 0 must dissipate, so that the energy test can tell them apart.
TEST(Newmark, PositiveDeltaDissipatesEnergy) {
  FreeVibration p = free_vibration();
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(p.system, implicit_coefficients(NewmarkParams{.delta = 0.3}),
                                    p.dt));
  State s = p.initial;
  s.a = consistent_acceleration(p.system, s);
  const double e0 = p.system.energy(s.u, s.v);
  for (int i = 0; i < 3000; ++i) integrator.step(p.system, s);
  EXPECT_LT(p.system.energy(s.u, s.v), (1.0 - 1e-4) * e0);
}

// δ = 1 (β = 1, γ = 3/2) and backward Euler share the two-step form (1+Ω²)u₊ − 2u + u₋ = 0
// with the same start (a₀ = 0 on the rod), so their displacements and contact forces coincide
// on the impact problem; their velocities differ (not asserted).
TEST(Newmark, DeltaOneGivesBackwardEulerPressures) {
  const RodScene scene;
  const double p_scale = derive(scene).pressure_scale;
  const testing::Run newmark = run(scene, NewmarkParams{.delta = 1.0});
  const testing::Run euler = run(scene, BackwardEulerParams{});
  ASSERT_EQ(newmark.summary.status, RunStatus::ok);
  ASSERT_EQ(euler.summary.status, RunStatus::ok);
  ASSERT_EQ(newmark.trace.size(), euler.trace.size());
  EXPECT_LE(max_abs_difference(newmark.trace.pressure, euler.trace.pressure), 1e-9 * p_scale);
  EXPECT_LE(max_abs_difference(newmark.trace.displacement, euler.trace.displacement),
            1e-9 * scene.gap);
  // Not trivially equal: there is a contact pulse to compare.
  EXPECT_GT(*std::max_element(euler.trace.pressure.begin(), euler.trace.pressure.end()),
            0.5 * p_scale);
}

// The δ form is only a parametrisation of (β, γ): both spellings must run the same method.
TEST(Newmark, DeltaFormEqualsExplicitBetaGammaForm) {
  const RodScene scene;
  for (double delta : {0.1, 0.3, 0.7}) {
    const testing::Run by_delta = run(scene, NewmarkParams{.delta = delta});
    const testing::Run by_coefficients =
        run(scene, NewmarkParams{.coefficients = newmark_from_delta(delta)});
    ASSERT_EQ(by_delta.summary.status, RunStatus::ok) << delta;
    EXPECT_EQ(by_delta.trace.pressure, by_coefficients.trace.pressure) << delta;
    EXPECT_EQ(by_delta.trace.velocity, by_coefficients.trace.velocity) << delta;
  }
}

// The explicit (β, γ) form must reach parameters outside eq. 13, e.g. Fox–Goodwin β = 1/12,
// γ = 1/2: a different method, so a different trace from the trapezoidal rule.
TEST(Newmark, ExplicitCoefficientsOutsideTheDeltaFamily) {
  FreeVibration p = free_vibration();
  ImplicitIntegrator fox_goodwin;
  const ImplicitCoefficients c =
      implicit_coefficients(NewmarkParams{.coefficients = BetaGamma{1.0 / 12.0, 0.5}});
  EXPECT_DOUBLE_EQ(c.b1, 1.0 / 12.0);
  ASSERT_TRUE(fox_goodwin.initialize(p.system, c, p.dt));
  State s = p.initial;
  s.a = consistent_acceleration(p.system, s);
  for (int i = 0; i < 50; ++i) fox_goodwin.step(p.system, s);
  const State trapezoid =
      testing::run_implicit(p.system, implicit_coefficients(NewmarkParams{.delta = 0.0}), p.dt,
                            50, p.initial);
  EXPECT_GT((s.u - trapezoid.u).norm(), 1e-9 * p.initial.u.norm());
}

}  // namespace
}  // namespace impactid
