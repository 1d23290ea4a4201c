// Houbolt's method (core/methods/houbolt.hpp): second order measured by halving Δt against the
// exact modal solution, with and without damping; the start-up keeps the local error of Houbolt's
// own cubic (O(Δt⁴) in u, O(Δt³) in v); every step satisfies Houbolt's difference formulas (and the
// start's) and the equation of motion, checked with dense matrices; the spectral analysis
// against closed forms (period error 11/24·Ω², ρ∞ = 0, ρ ~ Ω^(−2/3), ξ̄ ~ Ω³/2) and against the
// stepper itself; a free mass leaves the wall at most at 5/6 of its speed; the Signorini
// conditions at every step on the paper's rod, between two walls, on a scene of bodies and on
// sparse models; the rod batched (tests/batched_simulation_test.cpp), scenes of bodies not.
#include "core/methods/houbolt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"
#include "core/spectral/amplification.hpp"
#include "signorini_check.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::damped_free_rod;
using testing::dense_mode;
using testing::energy_norm_error;
using testing::expect_signorini;
using testing::free_rod;
using testing::initial_state;
using testing::make_state;
using testing::ModalExact;
using testing::observed_orders;
using testing::record_signorini;
using testing::SignoriniRecord;

using TridiagonalHoubolt = Houbolt<ImplicitIntegrator, SecondOrderSystem>;

// Relative energy-norm errors at T = 1 of the first elastic mode started displaced,
// Δt = T/40 … T/640.
std::vector<double> mode_errors(double a1) {
  const SecondOrderSystem system = damped_free_rod(a1);
  const testing::Mode mode = dense_mode(system, 1);
  const ModalExact exact{mode.omega, 0.5 * a1 * mode.omega};
  std::vector<double> errors;
  for (long steps = 40; steps <= 640; steps *= 2) {
    State s = make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size()));
    s.a = consistent_acceleration(system, s);
    TridiagonalHoubolt stepper;
    EXPECT_TRUE(stepper.initialize(system, 1.0 / steps));
    for (long i = 0; i < steps; ++i) stepper.step(system, s);
    errors.push_back(energy_norm_error(system, mode.omega, s.u - mode.phi * exact.q(1.0),
                                       s.v - mode.phi * exact.dq(1.0)) /
                     mode.omega);
  }
  return errors;
}

TEST(Houbolt, IsSecondOrderWithAndWithoutDamping) {
  for (const double a1 : {0.0, 0.02}) {
    const std::vector<double> errors = mode_errors(a1);
    const std::vector<double> orders = observed_orders(errors);
    EXPECT_LT(errors.back(), 1e-3) << a1;
    for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
      EXPECT_NEAR(orders[k], 2.0, 0.1) << a1 << " " << k;
    }
  }
}

// The start-up (steps 1 and 2) and the first Houbolt step: the errors after 1, 2 and 3 steps,
// from the mode with both u and v non-zero, fall like Δt⁴ in u and Δt³ in v (the cubic's own
// local orders), at Δt = T/20 … T/160 of T = 1.
TEST(Houbolt, StartUpKeepsTheLocalErrorOfTheCubic) {
  const SecondOrderSystem system = damped_free_rod(0.0);
  const testing::Mode mode = dense_mode(system, 1);
  const double w = mode.omega;
  for (int after = 1; after <= 3; ++after) {
    std::vector<double> u_errors, v_errors;
    for (long division = 20; division <= 160; division *= 2) {
      const double dt = 1.0 / division, t = after * dt;
      State s = make_state(mode.phi, w * mode.phi);  // u = φ(cos ωt + sin ωt)
      s.a = consistent_acceleration(system, s);
      TridiagonalHoubolt stepper;
      ASSERT_TRUE(stepper.initialize(system, dt));
      for (int i = 0; i < after; ++i) stepper.step(system, s);
      u_errors.push_back((s.u - mode.phi * (std::cos(w * t) + std::sin(w * t))).norm());
      v_errors.push_back((s.v - mode.phi * w * (std::cos(w * t) - std::sin(w * t))).norm());
    }
    for (const double order : observed_orders(u_errors)) EXPECT_GT(order, 3.8) << after;
    for (const double order : observed_orders(v_errors)) EXPECT_GT(order, 2.8) << after;
  }
}

// Every step against the formulas as Houbolt wrote them (not as core/methods/houbolt.hpp rearranges
// them), and the equation of motion M·a + C·v + K·u = 0 at every step, with dense matrices.
TEST(Houbolt, StepsSatisfyHouboltsFormulasAndTheEquationOfMotion) {
  const SecondOrderSystem system = damped_free_rod(0.02);
  const testing::Mode mode = dense_mode(system, 2);
  const double dt = 0.03;
  State s = make_state(mode.phi, 0.7 * mode.omega * mode.phi);
  s.a = consistent_acceleration(system, s);
  const Eigen::MatrixXd m = system.mass.dense(), c = system.damping.dense(),
                        k = system.stiffness.dense();
  std::vector<State> states{s};
  TridiagonalHoubolt stepper;
  ASSERT_TRUE(stepper.initialize(system, dt));
  for (int i = 0; i < 12; ++i) {
    stepper.step(system, s);
    states.push_back(s);
  }
  const double scale = mode.omega * mode.omega * mode.phi.norm();  // |a|
  const double tolerance = 1e-10 * scale;
  for (std::size_t n = 1; n < states.size(); ++n) {
    const State& x = states[n];
    EXPECT_LT((m * x.a + c * x.v + k * x.u).norm(), tolerance) << n;
  }
  // Step 1: the linear-acceleration step.
  const State &s0 = states[0], &s1 = states[1], &s2 = states[2];
  EXPECT_LT((s1.u - s0.u - dt * s0.v - dt * dt * (s0.a / 3.0 + s1.a / 6.0)).norm(),
            tolerance * dt * dt);
  EXPECT_LT((s1.v - s0.v - 0.5 * dt * (s0.a + s1.a)).norm(), tolerance * dt);
  // Step 2: the cubic through u₀, v₀, u₁, u₂.
  EXPECT_LT(
      (s2.a - (5.0 * s2.u - 16.0 * s1.u + 11.0 * s0.u + 6.0 * dt * s0.v) / (2 * dt * dt)).norm(),
      tolerance);
  EXPECT_LT((s2.v - s0.v - 2.0 * (s2.u - 2.0 * s1.u + s0.u) / dt).norm(), tolerance * dt);
  // Houbolt's formulas from step 3 on.
  for (std::size_t n = 3; n < states.size(); ++n) {
    const Eigen::VectorXd &u1 = states[n].u, &u0 = states[n - 1].u, &um1 = states[n - 2].u,
                          &um2 = states[n - 3].u;
    EXPECT_LT((states[n].a - (2.0 * u1 - 5.0 * u0 + 4.0 * um1 - um2) / (dt * dt)).norm(), tolerance)
        << n;
    EXPECT_LT((states[n].v - (11.0 * u1 - 18.0 * u0 + 9.0 * um1 - 2.0 * um2) / (6.0 * dt)).norm(),
              tolerance * dt)
        << n;
  }
}

// On ü + u = 0 (Ω = Δt): (2 + Ω²)λ³ − 5λ² + 4λ − 1 = 0. With λ = e^z, 2 − 5e^(−z) + 4e^(−2z) −
// e^(−3z) = z² − (11/12)z⁴ + z⁵ + … = −Ω², so z = iΩ(1 − (11/24)Ω²) − Ω⁴/2 + …: the period error
// is 11/24·Ω² and ξ̄ = Ω³/2 to leading order; as Ω → ∞, λ³ ≈ 1/Ω², ρ → 0 like Ω^(−2/3).
TEST(Houbolt, SpectralPropertiesAgainstClosedForms) {
  const MethodParams houbolt = HouboltParams{};
  EXPECT_NEAR(period_error_coefficient(houbolt), 11.0 / 24.0, 1e-9);
  EXPECT_EQ(high_frequency_spectral_radius(houbolt), 0.0);
  for (const double omega : {1e4, 1e6}) {
    EXPECT_NEAR(spectral_properties(houbolt, omega).spectral_radius * std::cbrt(omega * omega), 1.0,
                1e-2)
        << omega;
  }
  const double small = 0.01;
  EXPECT_NEAR(spectral_properties(houbolt, small).damping_ratio / (0.5 * small * small * small),
              1.0, 1e-2);
  EXPECT_NEAR(spectral_properties(houbolt, 0.05).period_error, 11.0 / 24.0 * 0.05 * 0.05,
              1e-2 * 11.0 / 24.0 * 0.05 * 0.05);
  EXPECT_TRUE(is_stable(houbolt, 1e6));
  // Dissipative at every Ω (below 1e-2, 1 − ρ ≈ Ω⁴/2 is under the rounding of ρ).
  EXPECT_LT(max_spectral_radius(houbolt, 1e-2, 1e6, 801), 1.0);

  // The eigenvalues of the companion matrix (double, Eigen, no rescaling) are the ones reported.
  for (const double omega : {0.5, 2.0, 50.0}) {
    const Eigen::MatrixXd a = amplification_matrix(houbolt, omega);
    ASSERT_EQ(a.rows(), 3);
    const double rho = testing::spectral_radius_of(a);
    EXPECT_NEAR(spectral_properties(houbolt, omega).spectral_radius, rho, 1e-12 * rho) << omega;
  }
}

// The companion matrix is the recurrence the stepper runs: on a one-dof oscillator (ω = 1),
// from the fourth step on, u_{n+1} = A·(u_n, u_{n−1}, u_{n−2}).
TEST(Houbolt, CompanionMatrixIsWhatTheStepperDoes) {
  SecondOrderSystem oscillator;
  oscillator.mass = Tridiagonal::zero(1);
  oscillator.mass.diag[0] = 1.0;
  oscillator.stiffness = oscillator.mass;
  oscillator.damping = Tridiagonal::zero(1);
  for (const double omega : {0.3, 1.7, 40.0}) {
    State s = make_state(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 0.4));
    s.a = consistent_acceleration(oscillator, s);
    TridiagonalHoubolt stepper;
    ASSERT_TRUE(stepper.initialize(oscillator, omega));
    std::vector<double> u{s.u[0]};
    for (int i = 0; i < 8; ++i) {
      stepper.step(oscillator, s);
      u.push_back(s.u[0]);
    }
    const Eigen::MatrixXd a = amplification_matrix(HouboltParams{}, omega);
    for (std::size_t n = 3; n + 1 < u.size(); ++n) {
      const double predicted = a(0, 0) * u[n] + a(0, 1) * u[n - 1] + a(0, 2) * u[n - 2];
      EXPECT_NEAR(u[n + 1], predicted, 1e-13) << omega << " " << n;
    }
  }
}

// A mass without spring (m = 1) flying at v0 = 1 onto a wall 1 ahead: the step that puts it on
// the wall gives it Houbolt's velocity v_{n+1} = (11·gap − 18u_n + 9u_{n−1} − 2u_{n−2})/(6Δt),
// which after a flight at v0 is (11δ − 5Δt·v0)/(6Δt), δ = gap − u_n < Δt·v0: it leaves at most at
// 5/6 of its speed (where the Wilson-θ and trapezoidal updates leave at up to 2 and 1 times it).
TEST(Houbolt, AFreeMassLeavesTheWallSlowerThanItCame) {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(1);
  system.mass.diag[0] = 1.0;
  system.stiffness = Tridiagonal::zero(1);
  system.damping = Tridiagonal::zero(1);
  system.contact_dof = 0;
  system.gap = 1.0;
  for (const double dt : {0.33, 0.3, 0.26, 0.2}) {
    State s = make_state(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
    s.a = consistent_acceleration(system, s);
    TridiagonalHoubolt stepper;
    ASSERT_TRUE(stepper.initialize(system, dt));
    std::vector<double> u{s.u[0]};
    while (s.u[0] + dt * s.v[0] <= system.gap) {
      stepper.step(system, s);
      ASSERT_EQ(s.lambda, 0.0);
      u.push_back(s.u[0]);
    }
    ASSERT_GE(u.size(), 3u);
    const std::size_t n = u.size() - 1;
    stepper.step(system, s);
    EXPECT_GT(s.lambda, 0.0);
    EXPECT_EQ(s.u[0], system.gap);
    EXPECT_NEAR(s.v[0],
                (11.0 * system.gap - 18.0 * u[n] + 9.0 * u[n - 1] - 2.0 * u[n - 2]) / (6 * dt),
                1e-12)
        << dt;
    const double delta = system.gap - u[n];
    EXPECT_NEAR(s.v[0], (11.0 * delta - 5.0 * dt) / (6.0 * dt), 1e-12) << dt;
    EXPECT_LT(std::abs(s.v[0]), 5.0 / 6.0 + 1e-12) << dt;
  }
}

// Steps `system` with Houbolt from its scene's start, recording every step's Signorini values.
template <class Integrator, class System>
SignoriniRecord step_scene(const System& system, State s, double dt, long steps) {
  s.a = consistent_acceleration(system, s);
  Houbolt<Integrator, System> stepper;
  EXPECT_TRUE(stepper.initialize(system, dt));
  SignoriniRecord record;
  for (long i = 0; i < steps; ++i) {
    stepper.step(system, s);
    record_signorini(system, s, record);
  }
  return record;
}

// The paper's rod: at every step λ >= 0, the node not beyond the wall, and on it where λ > 0;
// then through simulate(), whose every sample has p >= 0 and u_c <= gap; batchable (the batched
// kernel's lanes equal simulate()'s: tests/batched_simulation_test.cpp).
TEST(Houbolt, SignoriniConditionsHoldAtEveryStepOfThePapersRod) {
  const RodScene rod;
  const AssembledScene scene = assemble(rod);
  expect_signorini(step_scene<ImplicitIntegrator>(scene.system, initial_state(scene, 0), scene.dt,
                                                  scene.step_count),
                   rod.gap, 100);

  const testing::Run run = testing::run(rod, HouboltParams{});
  EXPECT_EQ(run.summary.status, RunStatus::ok) << run.summary.message;
  EXPECT_EQ(run.summary.steps, run.summary.planned_steps);
  for (std::size_t i = 0; i < run.trace.pressure.size(); ++i) {
    ASSERT_GE(run.trace.pressure[i], 0.0) << i;
    ASSERT_LE(run.trace.displacement[i], rod.gap * (1.0 + 1e-12)) << i;
  }
  EXPECT_TRUE(batchable(rod, HouboltParams{}, RunOptions{}));
  // Skipping the rigid free flight starts the method later; its start reproduces rigid motion
  // exactly, so the run is the stepped one to round-off.
  const testing::Run skipped = testing::run(rod, HouboltParams{}, RunOptions{});
  EXPECT_LT(testing::max_abs_difference(skipped.trace.pressure, run.trace.pressure),
            1e-6 * *std::max_element(run.trace.pressure.begin(), run.trace.pressure.end()));
}

// The rod between two walls, and a scene of bodies (a striker, a target, a right wall): both
// walls, the pair and the wall keep the conditions at every step; simulate() agrees.
TEST(Houbolt, SignoriniConditionsHoldBetweenTwoWallsAndInAsceneOfBodies) {
  RodScene rod;
  rod.far_gap = 0.005;
  rod.t_end = 3e-4;
  const AssembledScene two_walls = assemble(rod);
  ASSERT_TRUE(two_walls.system.has_far_contact());
  expect_signorini(step_scene<ImplicitIntegrator>(two_walls.system, initial_state(two_walls, 0),
                                                  two_walls.dt, two_walls.step_count),
                   rod.gap, 100);

  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  const AssembledScene scene = assemble(bodies);
  ASSERT_EQ(scene.system.constraints.size(), 2u);
  expect_signorini(step_scene<ImplicitIntegrator>(scene.system, initial_state(scene, 2), scene.dt,
                                                  scene.step_count),
                   0.01, 100);
  SimulationWorkspace ws;
  const RunSummary summary = simulate(scene, HouboltParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12 * 0.01);
  EXPECT_FALSE(chain_batchable(scene, HouboltParams{}, RunOptions{}));
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// Sparse models: the paper's rod as a sparse system equals the tridiagonal run to round-off
// through the impact's first steps (as tests/sparse_model_test.cpp compares the single-step
// family; later the chatter's round-off decides steps), and keeps the conditions at every step;
// the shipped block model (1722 DOFs, 41 contacts) runs `ok` with no penetration.
TEST(Houbolt, SparseModelsKeepTheConditions) {
  const testing::SparseRodPair pair = testing::sparse_rod_pair();
  const RodScene& rod = pair.rod;
  const SecondOrderSystem& tri = pair.tridiagonal;
  const SparseSystem& sys = pair.sparse;
  const Eigen::Index n = tri.size();
  const RodSceneDerived d = derive(rod);
  State a = pair.start;
  State b = a;
  TridiagonalHoubolt x;
  Houbolt<SparseImplicitIntegrator, SparseSystem> y;
  ASSERT_TRUE(x.initialize(tri, d.time_step));
  ASSERT_TRUE(y.initialize(sys, d.time_step));
  const long steps = static_cast<long>(d.impact_time / d.time_step) + 40;
  double worst = 0.0, largest = 0.0;
  for (long i = 0; i < steps; ++i) {
    x.step(tri, a);
    y.step(sys, b);
    worst = std::max(worst, (a.u - b.u).lpNorm<Eigen::Infinity>());
    largest = std::max(largest, a.u.lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-11 * largest);
  State start = make_state(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(n, rod.velocity));
  start.multipliers = Eigen::VectorXd::Zero(1);
  expect_signorini(step_scene<SparseImplicitIntegrator>(sys, start, d.time_step, d.step_count),
                   rod.gap, 50);

  const Simulation block = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*block.model());
  ASSERT_TRUE(scene.sparse);
  SimulationWorkspace ws;
  const RunSummary summary = simulate(scene, HouboltParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-9 * 0.001);
  for (const auto& contact : ws.trace.contact_pressure) {
    EXPECT_GE(*std::min_element(contact.begin(), contact.end()), 0.0);
  }
}

}  // namespace
}  // namespace impactid
