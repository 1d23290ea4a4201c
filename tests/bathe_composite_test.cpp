// The Bathe family (core/methods/bathe_composite.hpp, core/methods/method.hpp): second order
// measured by halving Δt against the exact modal solution; ρ∞-Bathe with ρ∞ = 1 and γ = ½ is the
// trapezoidal rule applied twice with Δt/2; ρ(Ω) tends to the ρ∞ asked for, never exceeds 1, and
// the period error is O(Ω²); the default γ₀ gives equal effective matrices; the Signorini
// conditions hold at every sample and at every sub-step of a rod hitting the wall; the scheme runs
// every kind of scene.
#include "core/methods/bathe_composite.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/exact_solution.hpp"
#include "core/run/simulation.hpp"
#include "core/spectral/amplification.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::dense_mode;
using testing::energy_norm_error;
using testing::free_rod;
using testing::make_state;
using testing::observed_orders;

State run_composite(const SecondOrderSystem& system, const MethodParams& method, double dt,
                    long steps, State state) {
  state.a = consistent_acceleration(system, state);
  BatheComposite<ImplicitIntegrator, SecondOrderSystem> stepper;
  EXPECT_TRUE(stepper.initialize(system, composite_coefficients(method), dt));
  for (long i = 0; i < steps; ++i) stepper.step(system, state);
  return state;
}

// Relative energy-norm errors at T = 1 of the first elastic mode of a free rod, Δt = T/40 … T/640
// (as tests/implicit_integrator_test.cpp measures the single-step methods).
std::vector<double> mode_errors(const MethodParams& method) {
  const SecondOrderSystem system = free_rod(10);
  const testing::Mode mode = dense_mode(system, 1);
  std::vector<double> errors;
  for (long steps = 40; steps <= 640; steps *= 2) {
    const State end = run_composite(system, method, 1.0 / steps, steps,
                                    make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size())));
    const Eigen::VectorXd u_exact = mode.phi * std::cos(mode.omega);
    const Eigen::VectorXd v_exact = -mode.omega * mode.phi * std::sin(mode.omega);
    errors.push_back(energy_norm_error(system, mode.omega, end.u - u_exact, end.v - v_exact) /
                     mode.omega);
  }
  return errors;
}

TEST(BatheComposite, IsSecondOrderForEveryRhoInfAndSubStepRatio) {
  for (const MethodParams& method :
       {MethodParams{BatheParams{}}, MethodParams{RhoBatheParams{}},
        MethodParams{RhoBatheParams{.rho_inf = 0.6}}, MethodParams{RhoBatheParams{.rho_inf = 1.0}},
        MethodParams{RhoBatheParams{.rho_inf = 0.3, .gamma = 0.3}}}) {
    const std::vector<double> errors = mode_errors(method);
    const std::vector<double> orders = observed_orders(errors);
    EXPECT_LT(errors.back(), 1e-3) << to_string(kind_of(method));
    for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
      EXPECT_NEAR(orders[k], 2.0, 0.1) << to_string(kind_of(method)) << " " << k;
    }
  }
}

// ρ∞ = 1, γ = ½: q = (¼, ½, ¼), and the second sub-step is the trapezoidal rule from t + Δt/2.
TEST(BatheComposite, RhoInfOneWithHalfStepsIsTheTrapezoidalRuleTwice) {
  const SecondOrderSystem system = free_rod(12, MassMatrix::consistent);
  const testing::Mode mode = dense_mode(system, 2);
  const State start = make_state(mode.phi, 0.3 * mode.phi);
  const State composite =
      run_composite(system, RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}, 0.02, 50, start);
  const State trapezoidal = testing::run_implicit(
      system, implicit_coefficients(NewmarkParams{.delta = 0.0}), 0.01, 100, start);
  EXPECT_LT((composite.u - trapezoidal.u).norm(), 1e-12 * trapezoidal.u.norm());
  EXPECT_LT((composite.v - trapezoidal.v).norm(), 1e-12 * trapezoidal.v.norm());
  const CompositeCoefficients c = composite_coefficients(RhoBatheParams{.rho_inf = 1.0});
  EXPECT_EQ(c.gamma, 0.5);
  EXPECT_EQ(c.q0, 0.25);
  EXPECT_EQ(c.q1, 0.5);
  EXPECT_EQ(c.q2, 0.25);
}

// The original scheme: γ = ½ and the 3-point backward Euler formula, q = (⅓, ⅓, ⅓) (Bathe 2007).
// The default γ₀ of ρ∞-Bathe makes q2 = γ/2, so both sub-steps have the same effective matrix.
TEST(BatheComposite, CoefficientsOfTheOriginalSchemeAndOfTheDefaultRatio) {
  const CompositeCoefficients bathe = composite_coefficients(BatheParams{});
  EXPECT_EQ(bathe.gamma, 0.5);
  EXPECT_NEAR(bathe.q0, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(bathe.q1, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(bathe.q2, 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(rho_bathe_default_gamma(0.0), 2.0 - std::sqrt(2.0), 1e-15);
  for (const double rho : {0.0, 0.2, 0.5, 0.9, 0.999, 1.0}) {
    const CompositeCoefficients c = composite_coefficients(RhoBatheParams{.rho_inf = rho});
    EXPECT_NEAR(c.q2, c.gamma / 2.0, 1e-12) << rho;
    EXPECT_NEAR(c.first.b1 * c.gamma * c.gamma, c.second.b1, 1e-12) << rho;  // (γ/2)² = q2²
  }
}

// TR-BDF2 (γ = 2 − √2) is ρ∞-Bathe with ρ∞ = 0 at that γ: the same coefficients, and its
// second sub-step is BDF2 over the unequal steps γΔt, (1 − γ)Δt: with the trapezoidal relation,
// u₁ = (u_γ − (1−γ)²·u₀)/(γ(2−γ)) + (1−γ)/(2−γ)·Δt·v₁. Checked on the weights: q0 = q1 (the
// v₀ + v_γ that the trapezoidal relation turns into u_γ − u₀), 2·q0/γ = 1/(γ(2−γ)) and
// q2 = (1−γ)/(2−γ).
TEST(BatheComposite, TrBdf2IsRhoBatheAtRhoInfZeroAndItsSecondSubStepIsBdf2) {
  const CompositeCoefficients c = composite_coefficients(TrBdf2Params{});
  const CompositeCoefficients r = composite_coefficients(RhoBatheParams{.rho_inf = 0.0});
  const double g = 2.0 - std::sqrt(2.0);
  EXPECT_NEAR(c.gamma, g, 1e-15);
  EXPECT_EQ(c.gamma, r.gamma);
  EXPECT_EQ(c.q0, r.q0);
  EXPECT_EQ(c.q1, r.q1);
  EXPECT_EQ(c.q2, r.q2);
  EXPECT_NEAR(c.q0, c.q1, 1e-15);
  EXPECT_NEAR(2.0 * c.q0 / g, 1.0 / (g * (2.0 - g)), 1e-14);
  EXPECT_NEAR(c.q2, (1.0 - g) / (2.0 - g), 1e-15);
  const RodScene rod;
  SimulationWorkspace a, b;
  simulate(rod, TrBdf2Params{}, RunOptions{}, a);
  simulate(rod, RhoBatheParams{}, RunOptions{}, b);
  ASSERT_EQ(a.trace.pressure.size(), b.trace.pressure.size());
  for (std::size_t i = 0; i < a.trace.pressure.size(); ++i) {
    ASSERT_EQ(a.trace.pressure[i], b.trace.pressure[i]) << i;
  }
  EXPECT_NEAR(high_frequency_spectral_radius(TrBdf2Params{}), 0.0, 1e-6);  // L-stable
}

TEST(BatheComposite, SpectralRadiusTendsToRhoInfAndNeverExceedsOne) {
  for (const double rho : {0.0, 0.3, 0.6, 0.9, 1.0}) {
    const MethodParams method = RhoBatheParams{.rho_inf = rho};
    EXPECT_NEAR(high_frequency_spectral_radius(method), rho, 1e-6) << rho;
    EXPECT_TRUE(is_stable(method, 1e6)) << rho;
    // Second order: the period error is c·Ω² + O(Ω⁴), finite c.
    const double c = period_error_coefficient(method);
    EXPECT_TRUE(std::isfinite(c)) << rho;
    const SpectralProperties p = spectral_properties(method, 0.05);
    EXPECT_NEAR(p.period_error, c * 0.05 * 0.05, 1e-2 * std::abs(c) * 0.05 * 0.05) << rho;
    EXPECT_LT(std::abs(1.0 - p.spectral_radius), 1e-4) << rho;  // little low-frequency damping
  }
  EXPECT_NEAR(high_frequency_spectral_radius(BatheParams{}), 0.0, 1e-6);
  // ρ∞ = 1, γ = ½: the trapezoidal rule's period error at Ω/2 taken twice: c = 1/12 · ¼.
  EXPECT_NEAR(period_error_coefficient(RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}), 1.0 / 48,
              1e-10);
  // The amplification matrix is the composed one: two trapezoidal half steps.
  const Eigen::MatrixXd a = amplification_matrix(RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}, 0.7);
  const Eigen::MatrixXd half = amplification_matrix(NewmarkParams{.delta = 0.0}, 0.35);
  const Eigen::Vector3d d(1.0, 0.5, 0.25);  // (u, Δt·v, Δt²·a) of the half step
  const Eigen::MatrixXd twice = d.cwiseInverse().asDiagonal() * half * half * d.asDiagonal();
  EXPECT_LT((a - twice).norm(), 1e-13);
}

// A rod on the wall (the paper's scene): after every sub-step and every step the multiplier is
// >= 0 and the contact node is not beyond the wall; where λ > 0 it is on it.
TEST(BatheComposite, SignoriniConditionsHoldAtEverySubStepAndSample) {
  for (const MethodParams& method :
       {MethodParams{BatheParams{}}, MethodParams{RhoBatheParams{.rho_inf = 0.5}}}) {
    const RodScene rod;
    const AssembledScene scene = assemble(rod);
    const SecondOrderSystem& system = scene.system;
    State state = make_state(Eigen::VectorXd::Zero(system.size()), scene.initial_velocity);
    state.a = consistent_acceleration(system, state);
    BatheComposite<ImplicitIntegrator, SecondOrderSystem> stepper;
    ASSERT_TRUE(stepper.initialize(system, composite_coefficients(method), scene.dt));
    const Eigen::Index c = system.contact_dof;
    int pushing = 0;
    for (long i = 0; i < scene.step_count; ++i) {
      stepper.step(system, state);
      for (const State* s : {&stepper.substep_state(), static_cast<const State*>(&state)}) {
        ASSERT_GE(s->lambda, 0.0) << i;
        ASSERT_LE(s->u[c] - system.gap, 1e-12 * system.gap) << i;
        if (s->lambda > 0.0) {
          ASSERT_NEAR(s->u[c], system.gap, 1e-12 * system.gap) << i;
          ++pushing;
        }
      }
    }
    EXPECT_GT(pushing, 100) << to_string(kind_of(method));
  }
}

// Every kind of scene runs the composite schemes: the rod (ρ∞-Bathe's default within 5 % of the
// exact pressure: measured 2.3 %), batched (tests/batched_simulation_test.cpp), and a scene of
// two bodies, not batched.
TEST(BatheComposite, RunsTheRodBatchedAndAsceneOfBodiesUnbatched) {
  const RodScene rod;
  SimulationWorkspace ws;
  for (const MethodParams& method : {MethodParams{BatheParams{}}, MethodParams{RhoBatheParams{}}}) {
    const RunSummary summary = simulate(rod, method, RunOptions{}, ws);
    EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
    EXPECT_EQ(summary.steps, summary.planned_steps);
    EXPECT_TRUE(batchable(rod, method, RunOptions{}));
  }
  const RodImpactExact exact(rod);
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < ws.trace.pressure.size(); ++i) {
    const double p = exact.at_sample(static_cast<long>(i) + 1).pressure;
    error += std::abs(ws.trace.pressure[i] - p);
    norm += std::abs(p);
  }
  EXPECT_LT(error / norm, 0.05);

  Scene bodies;
  bodies.bodies = {Body{.name = "a", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "b", .gap = 0.01, .segments = {Segment{}}}};
  const AssembledScene scene = assemble(bodies);
  const RunSummary summary = simulate(scene, RhoBatheParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_FALSE(chain_batchable(scene, RhoBatheParams{}, RunOptions{}));
  double pushed = 0.0;
  for (const double p : ws.trace.pressure) {
    EXPECT_GE(p, 0.0);
    pushed = std::max(pushed, p);
  }
  EXPECT_GT(pushed, 0.0);
}

}  // namespace
}  // namespace impactid
