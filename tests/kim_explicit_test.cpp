// Kim's two-stage explicit scheme (core/methods/kim_explicit.hpp, KimExplicitParams in
// core/methods/method.hpp): its weights against the ones Kratos writes
// (explicit_multi_stage_kim_scheme.hpp) and against quadrature of a quadratic acceleration; second
// order measured by halving Δt against the exact modal solution, with and without damping; the
// amplification matrix against the stepper itself; ρ(Ω → 0) = 1, no Ω² period error, ξ̄ ≈ (3p −
// 1)/(144(1 − p))·Ω³; the stability limit Ω_crit(p) against a scan of ρ; p < ⅓ growing at small Ω;
// a run above the limit flagged and stopped; a run split in two equals one run (the state carries
// a₀); the Signorini conditions at every sample, stage and force point on the paper's rod, between
// two walls and in a scene of bodies; refusals, the registry and the command line.
#include "core/methods/kim_explicit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "cli_support.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/scene_reference.hpp"
#include "core/run/simulation.hpp"
#include "core/spectral/amplification.hpp"
#include "explicit_stepper_checks.hpp"
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
using testing::initial_state;
using testing::make_state;
using testing::ModalExact;
using testing::observed_orders;
using testing::record_signorini;
using testing::SignoriniRecord;

constexpr double kThird = 1.0 / 3.0;

Eigen::Matrix3d stepped_matrix(double p, double omega_dt) {
  return testing::stepped_matrix<KimExplicit>(kim_explicit_coefficients({.p = p}), omega_dt);
}

std::vector<double> mode_errors(double a1, double p) {
  return testing::first_mode_errors<KimExplicit>(a1, kim_explicit_coefficients({.p = p}));
}

// The weights as Kratos writes them (stage 2 and the final update, fraction p):
//   ũ₁: ½Δt²·((3p−1)/(3p)·a₀ + 1/(3p)·a_p),  ṽ₁: Δt·((2p−1)/(2p)·a₀ + 1/(2p)·a_p),
//   u₁: ½Δt²·((4p−1)/(6p)·a₀ − 1/(6p(p−1))·a_p + (2p−1)/(6(p−1))·a₁),
//   v₁: Δt·((3p−1)/(6p)·a₀ − 1/(6p(p−1))·a_p + (3p−2)/(6(p−1))·a₁).
TEST(KimExplicit, WeightsAreKratosAndIntegrateAQuadraticExactly) {
  for (const double p : {kThird, 0.4, 5.0 / 12.0, 0.45, 0.5}) {
    const KimExplicitCoefficients c = kim_explicit_coefficients({.p = p});
    EXPECT_NEAR(c.u0, 0.5 * (3.0 * p - 1.0) / (3.0 * p), 1e-15);
    EXPECT_NEAR(c.up, 0.5 / (3.0 * p), 1e-15);
    EXPECT_NEAR(c.v0, (2.0 * p - 1.0) / (2.0 * p), 1e-15);
    EXPECT_NEAR(c.vp, 1.0 / (2.0 * p), 1e-15);
    // u₁ and v₁ weights on (a₀, a_p, a₁).
    const double u_w[] = {c.u0 + c.cu * c.d0, c.up + c.cu * c.dp, c.cu * c.d1};
    const double v_w[] = {c.v0 + c.cv * c.d0, c.vp + c.cv * c.dp, c.cv * c.d1};
    EXPECT_NEAR(u_w[0], 0.5 * (4.0 * p - 1.0) / (6.0 * p), 1e-14) << p;
    EXPECT_NEAR(u_w[1], -0.5 / (6.0 * p * (p - 1.0)), 1e-14) << p;
    EXPECT_NEAR(u_w[2], 0.5 * (2.0 * p - 1.0) / (6.0 * (p - 1.0)), 1e-14) << p;
    EXPECT_NEAR(v_w[0], (3.0 * p - 1.0) / (6.0 * p), 1e-14) << p;
    EXPECT_NEAR(v_w[1], -1.0 / (6.0 * p * (p - 1.0)), 1e-14) << p;
    EXPECT_NEAR(v_w[2], (3.0 * p - 2.0) / (6.0 * (p - 1.0)), 1e-14) << p;
    // a(s) = s^k on s ∈ [0, 1]: v₁ − v₀ = ∫a = 1/(k+1), u₁ − u₀ − v₀ = ∫(1 − s)a = 1/((k+1)(k+2)).
    for (int k = 0; k <= 2; ++k) {
      const double a[] = {k == 0 ? 1.0 : 0.0, std::pow(p, k), 1.0};
      EXPECT_NEAR(v_w[0] * a[0] + v_w[1] * a[1] + v_w[2] * a[2], 1.0 / (k + 1), 1e-14) << p << k;
      EXPECT_NEAR(u_w[0] * a[0] + u_w[1] * a[1] + u_w[2] * a[2], 1.0 / ((k + 1) * (k + 2)), 1e-14)
          << p << " " << k;
      // The predictor: the line through a₀ and a_p, exact for k <= 1.
      if (k <= 1) {
        EXPECT_NEAR(c.v0 * a[0] + c.vp * a[1], 1.0 / (k + 1), 1e-14);
        EXPECT_NEAR(c.u0 * a[0] + c.up * a[1], 1.0 / ((k + 1) * (k + 2)), 1e-14);
      }
    }
  }
  // p = ½: the correction of u₁ vanishes exactly (u₁ = ũ₁, Simpson's rule for v₁).
  EXPECT_EQ(kim_explicit_coefficients({.p = 0.5}).cu, 0.0);
}

// Second order at every p with damping (the damping forces take the velocity predictors);
// without damping it converges faster.
TEST(KimExplicit, IsSecondOrderWithAndWithoutDamping) {
  for (const double p : {kThird, 0.4, 0.45, 0.5}) {
    const std::vector<double> damped = mode_errors(0.02, p);
    const std::vector<double> orders = observed_orders(damped);
    EXPECT_LT(damped.back(), 1e-3) << p;
    for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
      EXPECT_NEAR(orders[k], 2.0, 0.1) << p << " " << k;
    }
    // Undamped: third order, fourth at p = ⅓ (measured 3.000 and 4.001 from Δt = T/320 to
    // T/640), the period error O(Ω⁴) and at p = ⅓ also ξ̄ = O(Ω⁵).
    const std::vector<double> undamped = mode_errors(0.0, p);
    const std::vector<double> fast = observed_orders(undamped);
    EXPECT_LT(undamped.back(), 3e-9) << p;
    for (std::size_t k = fast.size() - 2; k < fast.size(); ++k) {
      EXPECT_NEAR(fast[k], p == kThird ? 4.0 : 3.0, 0.05) << p << " " << k;
    }
  }
}

TEST(KimExplicit, AmplificationMatrixIsWhatTheStepperDoes) {
  for (const double p : {kThird, 0.4, 0.45, 0.5}) {
    for (const double w : {0.01, 0.3, 1.0, 2.0, 2.4}) {
      const Eigen::MatrixXd analysed = amplification_matrix(KimExplicitParams{.p = p}, w);
      const Eigen::Matrix3d stepped = stepped_matrix(p, w);
      EXPECT_LT((analysed - stepped).cwiseAbs().maxCoeff(), 1e-13 * (1.0 + std::pow(w, 4)))
          << p << " " << w;
    }
  }
}

TEST(KimExplicit, SpectralPropertiesAtSmallAndModerateOmega) {
  for (const double p : {kThird, 0.4, 5.0 / 12.0, 0.45, 0.5}) {
    const KimExplicitParams params{.p = p};
    // No Ω² term in the period error: the Romberg extrapolation of PE/Ω² gives 0.
    EXPECT_NEAR(period_error_coefficient(params), 0.0, 1e-10) << p;
    // ρ(Ω → 0) = 1 and ξ̄ → (3p − 1)/(144(1 − p))·Ω³.
    const SpectralProperties tiny = spectral_properties(params, 1e-3);
    EXPECT_NEAR(tiny.spectral_radius, 1.0, 1e-12) << p;
    const double w = 0.02;
    const SpectralProperties small = spectral_properties(params, w);
    ASSERT_TRUE(small.oscillatory);
    const double xi = (3.0 * p - 1.0) / (144.0 * (1.0 - p));
    EXPECT_NEAR(small.damping_ratio / std::pow(w, 3), xi, 1e-3 * xi + 1e-9) << p;
    EXPECT_EQ(high_frequency_spectral_radius(params), std::numeric_limits<double>::infinity());
  }
  // The Ω⁴ period error: 1/720 at p = ⅓, 0 at p = 5/12, −1/480 at p = ½ (from a 40-digit
  // evaluation of the same matrix; the next term is O(Ω⁶)).
  const double w = 0.05;
  const auto quartic = [w](double p) {
    return spectral_properties(KimExplicitParams{.p = p}, w).period_error / std::pow(w, 4);
  };
  EXPECT_NEAR(quartic(kThird), 1.0 / 720.0, 2e-3 / 720.0);
  EXPECT_NEAR(quartic(5.0 / 12.0), 0.0, 1e-6);
  EXPECT_NEAR(quartic(0.5), -1.0 / 480.0, 2e-3 / 480.0);
  // p = ⅓ is nearly free of dissipation where the rod's modes live: ρ(1) = 0.99968, ρ(2) = 0.9516.
  EXPECT_NEAR(spectral_properties(KimExplicitParams{.p = kThird}, 1.0).spectral_radius, 0.999682,
              1e-6);
  EXPECT_NEAR(spectral_properties(KimExplicitParams{.p = kThird}, 2.0).spectral_radius, 0.951590,
              1e-6);
}

// Ω_crit(p) against a scan of ρ: ρ <= 1 below, ρ = 1 at it, ρ > 1 just past it.
TEST(KimExplicit, StabilityLimitIsTheClosedForm) {
  EXPECT_NEAR(kim_explicit_critical_omega(kThird), std::sqrt(6.0), 1e-14);
  EXPECT_NEAR(kim_explicit_critical_omega(0.5), std::sqrt(6.0), 1e-14);
  EXPECT_NEAR(kim_explicit_critical_omega(0.4), 2.0 * std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(kim_explicit_critical_omega(0.44175), 3.08151677, 1e-7);
  EXPECT_TRUE(std::isnan(kim_explicit_critical_omega(0.33)));
  EXPECT_TRUE(std::isnan(kim_explicit_critical_omega(0.51)));
  for (const double p : {kThird, 0.35, 0.375, 0.4, 0.42, 0.44, 0.4417, 0.442, 0.45, 0.475, 0.5}) {
    const KimExplicitParams params{.p = p};
    const double limit = kim_explicit_critical_omega(p);
    EXPECT_EQ(stability_limit_omega(params), limit);
    EXPECT_LE(max_spectral_radius(params, 1e-3, limit, 2000), 1.0 + 1e-9) << p;
    EXPECT_NEAR(spectral_properties(params, limit).spectral_radius, 1.0, 1e-9) << p;
    EXPECT_GT(spectral_properties(params, limit * (1.0 + 1e-4)).spectral_radius, 1.0 + 1e-7) << p;
    EXPECT_TRUE(is_stable(params, limit)) << p;
    EXPECT_FALSE(is_stable(params, limit * 1.001)) << p;
  }
}

// Below p = ⅓ the principal pair grows at small Ω already: the stepper's own matrix.
TEST(KimExplicit, BelowOneThirdItGrowsAtSmallSteps) {
  for (const double p : {0.2, 0.25, 0.3}) {
    for (const double w : {0.5, 1.0}) {
      const double rho = testing::spectral_radius_of(stepped_matrix(p, w));
      EXPECT_GT(rho, 1.0 + 1e-5) << p << " " << w;
    }
    const auto e = validate(KimExplicitParams{.p = p});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->field, "p");
  }
}

// The paper's rod (lumped: ω_max·Δt = 2·Courant): the stable step is Ω_crit/2·h/c; a step past it
// is flagged before the run and the run ends `unstable`; within it the run is `ok`.
TEST(KimExplicit, RunAboveTheLimitIsFlaggedAndStopped) {
  const double limit = kim_explicit_critical_omega(0.5) / 2.0;  // Courant number (default p)
  RodScene rod;
  const RodSceneDerived d = derive(rod);
  const double h_over_c = d.element_length / d.wave_speed;
  rod.courant = 0.98 * limit;
  testing::Run within = testing::run(rod, KimExplicitParams{});
  EXPECT_EQ(within.summary.status, RunStatus::ok) << within.summary.message;
  EXPECT_TRUE(within.summary.warning.empty()) << within.summary.warning;
  EXPECT_NEAR(within.summary.stable_dt, limit * h_over_c, 1e-12 * h_over_c);

  rod.courant = 1.05 * limit;
  testing::Run above = testing::run(rod, KimExplicitParams{});
  EXPECT_EQ(above.summary.status, RunStatus::unstable) << above.summary.message;
  EXPECT_NE(above.summary.warning.find("exceeds kim-explicit's stable step"), std::string::npos)
      << above.summary.warning;
  EXPECT_LT(above.summary.steps, above.summary.planned_steps);

  rod.mass = MassMatrix::consistent;
  rod.courant = 0.5;
  testing::Run consistent = testing::run(rod, KimExplicitParams{});
  EXPECT_EQ(consistent.summary.stable_dt, 0.0);
  EXPECT_TRUE(consistent.summary.warning.empty());
}

// The state (u, v, a) is the whole of the scheme's memory: a free run stopped and started again
// from its state (a new stepper, initialised from it) goes on bit for bit.
TEST(KimExplicit, ARunSplitInTwoEqualsOneRun) {
  const SecondOrderSystem system = damped_free_rod(0.02);
  const testing::Mode mode = dense_mode(system, 2);
  State one = make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size()));
  one.a = consistent_acceleration(system, one);
  State split = one;
  const KimExplicitCoefficients c = kim_explicit_coefficients({.p = 0.4});
  KimExplicit whole, first, second;
  ASSERT_TRUE(whole.initialize(system, c, 0.01, one));
  ASSERT_TRUE(first.initialize(system, c, 0.01, split));
  for (int i = 0; i < 60; ++i) whole.step(system, one);
  for (int i = 0; i < 25; ++i) first.step(system, split);
  ASSERT_TRUE(second.initialize(system, c, 0.01, split));
  for (int i = 0; i < 35; ++i) second.step(system, split);
  EXPECT_EQ((one.u - split.u).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one.v - split.v).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one.a - split.a).cwiseAbs().maxCoeff(), 0.0);
}

// The gap of every constraint at u, as signorini_check.hpp computes it.
template <class F>
void for_each_gap(const SecondOrderSystem& system, const Eigen::VectorXd& u, F&& f) {
  for (std::size_t k = 0; k < system.constraints.size(); ++k) {
    f(static_cast<Eigen::Index>(k), testing::violation(system.constraints[k], u));
  }
  if (system.constraints.empty() && system.has_contact()) {
    f(-1, u[system.contact_dof] - system.gap);
  }
  if (system.constraints.empty() && system.has_far_contact()) {
    f(-2, -u[system.far_contact_dof] - system.far_gap);
  }
}
double multiplier(const State& s, Eigen::Index k) {
  return k == -1 ? s.lambda : k == -2 ? s.far_lambda : s.multipliers[k];
}

// Steps `system` from `s` and records, as the header states: each sample's λ₁ with the larger of
// the gaps at the sample u₁ and at the next force point u_p = u₁ + pΔt·v₁ + (pΔt)²/2·a₁ (it is
// complementary to the one that binds), each stage's λ_p with the gap at ũ₁ (recomputed here
// from the step's start and the stage's a_p), and every displacement the scheme computes: the
// sample, the stage's u_p.
SignoriniRecord step_scene(const SecondOrderSystem& system, State s, double dt, long steps,
                           double p = kThird) {
  s.a = consistent_acceleration(system, s);
  KimExplicit stepper;
  const KimExplicitCoefficients c = kim_explicit_coefficients({.p = p});
  EXPECT_TRUE(stepper.initialize(system, c, dt, s));
  SignoriniRecord record;
  for (long i = 0; i < steps; ++i) {
    const State start = s;
    stepper.step(system, s);
    const State& stage = stepper.substep_state();
    const Eigen::VectorXd predicted =
        start.u + dt * start.v + (c.u0 * dt * dt) * start.a + (c.up * dt * dt) * stage.a;
    const Eigen::VectorXd next = s.u + (p * dt) * s.v + (0.5 * p * p * dt * dt) * s.a;
    for_each_gap(system, s.u, [&](Eigen::Index k, double g) {
      double g_next = 0.0;
      for_each_gap(system, next, [&](Eigen::Index j, double gj) {
        if (j == k) g_next = gj;
      });
      record.record(std::max(g, g_next), multiplier(s, k));
      record.record(g, 0.0);
      record.record(g_next, 0.0);
    });
    for_each_gap(system, predicted,
                 [&](Eigen::Index k, double g) { record.record(g, multiplier(stage, k)); });
    State force_point = stage;
    force_point.lambda = force_point.far_lambda = 0.0;
    force_point.multipliers.setZero();
    record_signorini(system, force_point, record);
  }
  return record;
}

TEST(KimExplicit, SignoriniConditionsHoldAtEverySampleAndStageOfThePapersRod) {
  const RodScene rod;
  const AssembledScene scene = assemble(rod);
  for (const double p : {kThird, 0.4, 0.5}) {
    expect_signorini(
        step_scene(scene.system, initial_state(scene, 0), scene.dt, scene.step_count, p), rod.gap,
        100);
  }
  const testing::Run run = testing::run(rod, KimExplicitParams{});
  EXPECT_EQ(run.summary.status, RunStatus::ok) << run.summary.message;
  EXPECT_EQ(run.summary.steps, run.summary.planned_steps);
  for (std::size_t i = 0; i < run.trace.pressure.size(); ++i) {
    ASSERT_GE(run.trace.pressure[i], 0.0) << i;
    ASSERT_LE(run.trace.displacement[i], rod.gap) << i;
  }
  EXPECT_GT(*std::max_element(run.trace.pressure.begin(), run.trace.pressure.end()), 0.0);
  // A sweep runs it in the rod's batched kernel, bit for bit (tests/batched_explicit_test.cpp).
  EXPECT_TRUE(batchable(rod, KimExplicitParams{}, RunOptions{}));
}

TEST(KimExplicit, SignoriniConditionsHoldBetweenTwoWallsAndInASceneOfBodies) {
  RodScene rod;
  rod.far_gap = 0.005;
  rod.t_end = 6e-4;
  const AssembledScene two_walls = assemble(rod);
  ASSERT_TRUE(two_walls.system.has_far_contact());
  expect_signorini(
      step_scene(two_walls.system, initial_state(two_walls, 0), two_walls.dt, two_walls.step_count),
      rod.gap, 100);
  SimulationWorkspace ws;
  const RunSummary between = simulate(two_walls, KimExplicitParams{}, RunOptions{}, ws);
  EXPECT_EQ(between.status, RunStatus::ok) << between.message;
  EXPECT_LE(between.max_penetration, 0.0);
  EXPECT_GT(*std::max_element(ws.trace.far_pressure.begin(), ws.trace.far_pressure.end()), 0.0);

  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  const AssembledScene scene = assemble(bodies);
  ASSERT_EQ(scene.system.constraints.size(), 2u);
  for (const double p : {kThird, 0.45}) {
    expect_signorini(
        step_scene(scene.system, initial_state(scene, 2), scene.dt, scene.step_count, p), 0.01,
        100);
  }
  const RunSummary summary = simulate(scene, KimExplicitParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12 * 0.01);
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// A model of sparse matrices runs (the shipped block; the sparse stepper's checks are
// tests/sparse_explicit_test.cpp).
TEST(KimExplicit, RunsOnAModelOfSparseMatrices) {
  SimulationWorkspace ws;
  const Simulation block = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*block.model());
  ASSERT_TRUE(scene.sparse);
  const RunSummary summary = simulate(scene, KimExplicitParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12);
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// The registry: p (the key noh-bathe also takes) in [⅓, ½], reported with Ω_crit; a reference of
// another p is another reference.
TEST(KimExplicit, RegistryEntryAndRangeOfP) {
  for (const double p : {0.0, 0.3, 0.3333, 0.5000001, 0.54, 1.0, -1.0, std::nan(""),
                         std::numeric_limits<double>::infinity()}) {
    const auto e = validate(KimExplicitParams{.p = p});
    ASSERT_TRUE(e) << p;
    EXPECT_EQ(e->field, "p");
    EXPECT_EQ(e->value, format_value(p));
    EXPECT_NE(e->constraint.find("must lie in [1/3, 1/2]"), std::string::npos) << e->constraint;
  }
  for (const double p : {kThird, 0.4, 0.5}) EXPECT_FALSE(validate(KimExplicitParams{.p = p}));
  EXPECT_EQ(std::get<KimExplicitParams>(default_params(MethodKind::kim_explicit)).p, 0.5);
  EXPECT_EQ(std::string(to_string(MethodKind::kim_explicit)), "kim-explicit");

  MethodArguments given;
  given.set("p", 0.4);
  const auto built = build_method(MethodKind::kim_explicit, given);
  ASSERT_TRUE(std::holds_alternative<MethodParams>(built));
  const MethodParams& params = std::get<MethodParams>(built);
  EXPECT_EQ(std::get<KimExplicitParams>(params).p, 0.4);
  EXPECT_EQ(reported_value(params, "p"), 0.4);
  EXPECT_EQ(reported_value(params, "omega_crit"), kim_explicit_critical_omega(0.4));
  EXPECT_EQ(methods_taking("p"), "noh-bathe|kim-explicit");

  ReferenceOptions a, b;
  a.method = KimExplicitParams{.p = 0.4};
  b.method = KimExplicitParams{.p = 0.45};
  EXPECT_FALSE(a == b);
  b.method = KimExplicitParams{.p = 0.4};
  EXPECT_TRUE(a == b);
}

TEST(KimExplicit, CommandLine) {
  const testing::CommandOutput bad =
      testing::run_impactid("simulate --method kim-explicit --p 0.6");
  EXPECT_EQ(bad.status, 2) << bad.text;
  EXPECT_NE(bad.text.find("--p = 0.6: must lie in [1/3, 1/2]"), std::string::npos) << bad.text;
  const testing::CommandOutput ok =
      testing::run_impactid("simulate --method kim-explicit --p 0.4 --json");
  EXPECT_EQ(ok.status, 0) << ok.text;
  EXPECT_NE(ok.text.find("\"p\":0.4"), std::string::npos) << ok.text;
  EXPECT_NE(ok.text.find("\"status\":\"ok\""), std::string::npos) << ok.text;
  const testing::CommandOutput text = testing::run_impactid("simulate --method kim-explicit");
  EXPECT_EQ(text.status, 0) << text.text;
  EXPECT_NE(text.text.find("stable dt"), std::string::npos) << text.text;
  const testing::CommandOutput methods = testing::run_impactid("methods");
  EXPECT_EQ(methods.status, 0);
  EXPECT_NE(methods.text.find("kim-explicit\n  Kim two-stage explicit"), std::string::npos);
}

}  // namespace
}  // namespace impactid
