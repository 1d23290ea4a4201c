// Backward Euler (eqs 8–10): its closed-form per-step energy loss and its first step worked by
// hand on a two-mass system.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "core/methods/implicit_integrator.hpp"
#include "core/methods/method.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::dense_mode;
using testing::free_rod;
using testing::make_state;

// In modal coordinates a backward-Euler step solves [[1, −Ω], [Ω, 1]]·x₁ = x₀ for
// x = (ω·q, q̇), a scaled rotation: the modal energy shrinks by exactly 1/(1+Ω²) per step. This is
// the uncontrollable dissipation the paper blames for BE's large ε_p.
TEST(BackwardEuler, ModalEnergyDecaysByOnePlusOmegaSquaredPerStep) {
  const SecondOrderSystem system = free_rod(10);
  for (int k : {1, 3}) {
    const testing::Mode mode = dense_mode(system, k);
    const double dt = 0.05;
    const double omega_dt = mode.omega * dt;
    ImplicitIntegrator integrator;
    ASSERT_TRUE(integrator.initialize(system, implicit_coefficients(BackwardEulerParams{}), dt));
    State s = make_state(0.3 * mode.phi, 2.0 * mode.phi);  // any phase of the mode
    s.a = consistent_acceleration(system, s);
    const double e0 = system.energy(s.u, s.v);
    for (int i = 1; i <= 60; ++i) {
      integrator.step(system, s);
      const double expected = e0 * std::pow(1.0 + omega_dt * omega_dt, -i);
      ASSERT_NEAR(system.energy(s.u, s.v), expected, 1e-11 * expected) << "mode " << k << ", step " << i;
    }
  }
}

// Two unit masses joined by a unit spring, one step of Δt = 0.5 from u = (0, 0), v = (1, 0):
// u₁ = u₀ + Δt·v₁, v₁ = v₀ + Δt·a₁, M·a₁ + K·u₁ = 0 ⇒ (M + Δt²K)·u₁ = M·(u₀ + Δt·v₀).
// With M = I, K = [[1, −1], [−1, 1]]: [[1.25, −0.25], [−0.25, 1.25]]·u₁ = (0.5, 0)
// ⇒ u₁ = (5/12, 1/12), v₁ = (u₁ − u₀)/Δt = (5/6, 1/6), a₁ = (v₁ − v₀)/Δt = (−1/3, 1/3).
TEST(BackwardEuler, FirstStepWorkedByHand) {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(2);
  system.mass.diag << 1, 1;
  system.stiffness = Tridiagonal::zero(2);
  system.stiffness.diag << 1, 1;
  system.stiffness.upper << -1, 0;
  system.stiffness.lower << 0, -1;
  system.damping = Tridiagonal::zero(2);
  system.contact_dof = 1;
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(system, implicit_coefficients(BackwardEulerParams{}), 0.5));
  State s = make_state(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0));
  s.a = consistent_acceleration(system, s);
  integrator.step(system, s);
  EXPECT_NEAR(s.u[0], 5.0 / 12.0, 1e-15);
  EXPECT_NEAR(s.u[1], 1.0 / 12.0, 1e-15);
  EXPECT_NEAR(s.v[0], 5.0 / 6.0, 1e-15);
  EXPECT_NEAR(s.v[1], 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(s.a[0], -1.0 / 3.0, 1e-15);
  EXPECT_NEAR(s.a[1], 1.0 / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(s.t, 0.5);
}

// The same system, now with v₀ = (1, 1) and a wall at gap 0.05 for node 1. The free step gives
// u₁ = (0.5, 0.5), which penetrates, so the constrained step solves
// (M + Δt²K)·u₁ + Δt²·e₁·λ = M·(u₀ + Δt·v₀) = (0.5, 0.5) with u₁[1] = 0.05:
//   row 0: 1.25·u₁[0] − 0.25·0.05 = 0.5            ⇒ u₁[0] = 0.41
//   row 1: −0.25·0.41 + 1.25·0.05 + 0.25·λ = 0.5   ⇒ λ = 2.16
TEST(BackwardEuler, ContactStepWorkedByHand) {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(2);
  system.mass.diag << 1, 1;
  system.stiffness = Tridiagonal::zero(2);
  system.stiffness.diag << 1, 1;
  system.stiffness.upper << -1, 0;
  system.stiffness.lower << 0, -1;
  system.damping = Tridiagonal::zero(2);
  system.contact_dof = 1;
  system.gap = 0.05;
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(system, implicit_coefficients(BackwardEulerParams{}), 0.5));
  State s = make_state(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1));
  s.a = consistent_acceleration(system, s);
  EXPECT_TRUE(integrator.step(system, s));
  EXPECT_NEAR(s.u[0], 0.41, 1e-15);
  EXPECT_EQ(s.u[1], 0.05);
  EXPECT_NEAR(s.lambda, 2.16, 1e-14);
  EXPECT_NEAR(s.v[1], (0.05 - 0.0) / 0.5, 1e-15);
}

// No penetration tolerance: a free step that would overshoot the wall by only ε = 1e-12 must
// still be stopped, with the small force the algebra above gives for gap = 0.5 − ε:
// u₁[0] = 0.5 − 0.2·ε and λ = 4.8·ε.
TEST(BackwardEuler, TinyOvershootIsStillConstrained) {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(2);
  system.mass.diag << 1, 1;
  system.stiffness = Tridiagonal::zero(2);
  system.stiffness.diag << 1, 1;
  system.stiffness.upper << -1, 0;
  system.stiffness.lower << 0, -1;
  system.damping = Tridiagonal::zero(2);
  system.contact_dof = 1;
  const double eps = 1e-12;
  system.gap = 0.5 - eps;
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(system, implicit_coefficients(BackwardEulerParams{}), 0.5));
  State s = make_state(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1));
  s.a = consistent_acceleration(system, s);
  EXPECT_TRUE(integrator.step(system, s));
  EXPECT_EQ(s.u[1], system.gap);
  EXPECT_NEAR(s.u[0], 0.5 - 0.2 * eps, 1e-15);
  EXPECT_NEAR(s.lambda, 4.8 * eps, 0.01 * 4.8 * eps);
}

}  // namespace
}  // namespace impactid
