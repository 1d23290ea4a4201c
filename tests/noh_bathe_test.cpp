// The Noh–Bathe explicit scheme (core/methods/noh_bathe.hpp, NohBatheParams in
// core/methods/method.hpp): second order measured by halving Δt against the exact modal solution,
// with and without damping; the velocity weights; the amplification matrix against the stepper
// itself and against the closed forms (det, trace, ρ = √det where complex, period error
// −(3p−2)²/24·Ω², ξ̄ ≈ (1−p)²(2p−1)Ω³/8); the stability limit Ω_crit(p) from a scan of ρ and at both
// sides of it, p < ½ unstable at every Ω; a run above the limit flagged before it starts and
// stopped `unstable`; the Signorini conditions at every sample and sub-step on the paper's rod,
// between two walls and in a scene of bodies; refusals (range of p, keys, other contact laws,
// sparse models) and the command line.
#include "core/methods/noh_bathe.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
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

// Noh–Bathe's coefficients for any p, not validated: p < ½ is measured too.
NohBatheCoefficients unchecked_coefficients(double p) {
  NohBatheCoefficients c{};
  c.p = p;
  c.q1 = (1.0 - 2.0 * p) / (2.0 * p * (1.0 - p));
  c.q2 = 0.5 - p * c.q1;
  c.q0 = 0.5 - c.q1 - c.q2;
  return c;
}

Eigen::Matrix3d stepped_matrix(double p, double omega_dt) {
  return testing::stepped_matrix<NohBatheExplicit>(unchecked_coefficients(p), omega_dt);
}

std::vector<double> mode_errors(double a1, double p) {
  return testing::first_mode_errors<NohBatheExplicit>(a1, noh_bathe_coefficients({.p = p}));
}

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

TEST(NohBathe, IsSecondOrderWithAndWithoutDamping) {
  for (const double p : {0.5, 0.54, 0.7, 0.9}) {
    for (const double a1 : {0.0, 0.02}) {
      const std::vector<double> errors = mode_errors(a1, p);
      const std::vector<double> orders = observed_orders(errors);
      EXPECT_LT(errors.back(), 1e-3) << p << " " << a1;
      for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
        EXPECT_NEAR(orders[k], 2.0, 0.1) << p << " " << a1 << " " << k;
      }
    }
  }
}

// The weights of v₁ sum to one with the ½ on a_p, q2 = ½ − p·q1; p = ½ gives q0 = q1 = 0.
TEST(NohBathe, VelocityWeights) {
  for (const double p : {0.5, 0.54, 0.6, 0.8, 0.95}) {
    const NohBatheCoefficients c = noh_bathe_coefficients({.p = p});
    EXPECT_EQ(c.p, p);
    EXPECT_NEAR(c.q1, (1.0 - 2.0 * p) / (2.0 * p * (1.0 - p)), 1e-15);
    EXPECT_NEAR(c.q2, 0.5 - p * c.q1, 1e-15);
    EXPECT_NEAR(c.q0 + (0.5 + c.q1) + c.q2, 1.0, 1e-14) << p;
  }
  const NohBatheCoefficients half = noh_bathe_coefficients({.p = 0.5});
  EXPECT_EQ(half.q0, 0.0);
  EXPECT_EQ(half.q1, 0.0);
  EXPECT_EQ(half.q2, 0.5);
}

// The closed forms of NohBatheParams on (u, Δt·v) (a = −ω²u).
double closed_det(double p, double w) {
  return 1.0 - (1.0 - p) * (1.0 - p) * (2.0 * p - 1.0) * std::pow(w, 4) / 4.0;
}
double closed_trace(double p, double w) {
  return 2.0 - w * w + p * p * (1.0 - p) * std::pow(w, 4) / 2.0;
}

TEST(NohBathe, AmplificationMatrixIsWhatTheStepperDoes) {
  for (const double p : {0.5, 0.54, 0.75, 0.9}) {
    for (const double w : {0.01, 0.3, 1.0, 2.0, 3.0}) {
      const Eigen::MatrixXd analysed = amplification_matrix(NohBatheParams{.p = p}, w);
      const Eigen::Matrix3d stepped = stepped_matrix(p, w);
      EXPECT_LT((analysed - stepped).cwiseAbs().maxCoeff(), 1e-13 * (1.0 + std::pow(w, 4)))
          << p << " " << w;
      // On (u, Δt·v) with a = −ω²u the step is the 2×2 of the closed forms: the third column
      // enters as A = −Ω²·u.
      Eigen::Matrix2d two;
      two << stepped(0, 0) - w * w * stepped(0, 2), stepped(0, 1),
          stepped(1, 0) - w * w * stepped(1, 2), stepped(1, 1);
      EXPECT_NEAR(two.determinant(), closed_det(p, w), 1e-13 * (1.0 + std::pow(w, 4)));
      EXPECT_NEAR(two.trace(), closed_trace(p, w), 1e-13 * (1.0 + std::pow(w, 4)));
    }
  }
}

TEST(NohBathe, SpectralPropertiesAgainstClosedForms) {
  for (const double p : {0.5, 0.54, 0.6, 2.0 / 3.0, 0.7, 0.9}) {
    const NohBatheParams params{.p = p};
    // Period error −(3p − 2)²/24·Ω²: second order (−1/96 at p = ½, two half central-difference
    // steps).
    EXPECT_NEAR(period_error_coefficient(params), -(3.0 * p - 2.0) * (3.0 * p - 2.0) / 24.0, 1e-10)
        << p;
    // Where the principal pair is complex, ρ = √det exactly.
    for (const double w : {0.5, 1.0, 1.5, 2.0}) {
      const SpectralProperties s = spectral_properties(params, w);
      ASSERT_TRUE(s.oscillatory) << p << " " << w;
      EXPECT_NEAR(s.spectral_radius, std::sqrt(closed_det(p, w)), 1e-14) << p << " " << w;
    }
    // Ω → 0: ρ → 1 as 1 − (1−p)²(2p−1)Ω⁴/8 and ξ̄ → (1−p)²(2p−1)/8·Ω³.
    const double d = (1.0 - p) * (1.0 - p) * (2.0 * p - 1.0);
    const double w = 0.01;
    const SpectralProperties small = spectral_properties(params, w);
    EXPECT_NEAR(1.0 - small.spectral_radius, d * std::pow(w, 4) / 8.0, 1e-6 * std::pow(w, 4));
    if (d > 0.0) {
      EXPECT_NEAR(small.damping_ratio / std::pow(w, 3), d / 8.0, 1e-4 * d) << p;
    } else {
      EXPECT_NEAR(small.damping_ratio, 0.0, 1e-12);
    }
    // Explicit: no limit Ω → ∞.
    EXPECT_EQ(high_frequency_spectral_radius(params), std::numeric_limits<double>::infinity());
  }
  // p = ⅔ has no Ω² term in its period error, the least |period error| as Ω → 0.
  EXPECT_NEAR(period_error_coefficient(NohBatheParams{.p = 2.0 / 3.0}), 0.0, 1e-10);
  // The default is dissipative: ρ(2) = √(1 − 0.46²·0.08·4) = 0.9915.
  EXPECT_NEAR(spectral_properties(NohBatheParams{}, 2.0).spectral_radius,
              std::sqrt(1.0 - 0.46 * 0.46 * 0.08 * 4.0), 1e-14);
}

// Ω_crit(p) against a scan of ρ: ρ <= 1 below, ρ = 1 at it (the eigenvalue +1 for p <= ¾, −1
// above), ρ > 1 just past it; the closed values at p = ½, ⅔, ¾, and the limit 2 as p → 1.
TEST(NohBathe, StabilityLimitIsTheClosedForm) {
  EXPECT_EQ(noh_bathe_critical_omega(0.5), 4.0);
  EXPECT_NEAR(noh_bathe_critical_omega(0.54), 2.0 / std::sqrt(0.46 * 0.62), 1e-15);
  EXPECT_NEAR(noh_bathe_critical_omega(0.54), 3.745029431365691, 1e-14);
  EXPECT_NEAR(noh_bathe_critical_omega(2.0 / 3.0), 2.0 * std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(noh_bathe_critical_omega(0.75), std::sqrt(12.8), 1e-14);
  EXPECT_NEAR(noh_bathe_critical_omega(0.7501), 2.8143846, 1e-6);  // the −1 condition binds
  EXPECT_NEAR(noh_bathe_critical_omega(0.999999), 2.0, 1e-5);
  EXPECT_TRUE(std::isnan(noh_bathe_critical_omega(0.49)));
  EXPECT_TRUE(std::isnan(noh_bathe_critical_omega(1.0)));

  for (const double p : {0.5, 0.54, 0.6, 2.0 / 3.0, 0.7, 0.75, 0.76, 0.8, 0.9, 0.95}) {
    const NohBatheParams params{.p = p};
    const double limit = noh_bathe_critical_omega(p);
    EXPECT_EQ(stability_limit_omega(params), limit);
    EXPECT_LE(max_spectral_radius(params, 1e-3, limit, 2000), 1.0 + 1e-9) << p;
    EXPECT_NEAR(spectral_properties(params, limit).spectral_radius, 1.0, 1e-9) << p;
    EXPECT_GT(spectral_properties(params, limit * (1.0 + 1e-4)).spectral_radius, 1.0 + 1e-6) << p;
    EXPECT_TRUE(is_stable(params, limit)) << p;
    EXPECT_FALSE(is_stable(params, limit * 1.001)) << p;
  }
  EXPECT_EQ(stability_limit_omega(CentralDifferenceParams{}), 2.0);
  EXPECT_EQ(stability_limit_omega(HhtParams{}), std::numeric_limits<double>::infinity());
}

// Below p = ½ the determinant exceeds 1 at every Ω: the stepper's own matrix grows.
TEST(NohBathe, BelowOneHalfItIsUnstableForEveryStep) {
  for (const double p : {0.3, 0.45, 0.49}) {
    for (const double w : {0.1, 0.5, 1.0, 2.0}) {
      const Eigen::Matrix3d a = stepped_matrix(p, w);
      const double rho = testing::spectral_radius_of(a);
      EXPECT_GT(rho, 1.0 + 0.1 * (1.0 - p) * (1.0 - p) * (1.0 - 2.0 * p) * std::pow(w, 4))
          << p << " " << w;
    }
    const auto e = validate(NohBatheParams{.p = p});
    ASSERT_TRUE(e);
    EXPECT_EQ(e->field, "p");
  }
}

// The paper's rod (lumped: ω_max·Δt = 2·Courant): the stable step is Ω_crit/2·h/c; a step past it
// is flagged before the run and the run ends `unstable`; within it the run is `ok`.
TEST(NohBathe, RunAboveTheLimitIsFlaggedAndStopped) {
  const double limit = noh_bathe_critical_omega(0.54) / 2.0;  // Courant number
  RodScene rod;
  const RodSceneDerived d = derive(rod);
  const double h_over_c = d.element_length / d.wave_speed;
  rod.courant = 0.98 * limit;
  testing::Run within = testing::run(rod, NohBatheParams{});
  EXPECT_EQ(within.summary.status, RunStatus::ok) << within.summary.message;
  EXPECT_TRUE(within.summary.warning.empty()) << within.summary.warning;
  EXPECT_NEAR(within.summary.stable_dt, limit * h_over_c, 1e-12 * h_over_c);

  rod.courant = 1.05 * limit;
  testing::Run above = testing::run(rod, NohBatheParams{});
  EXPECT_EQ(above.summary.status, RunStatus::unstable) << above.summary.message;
  EXPECT_NE(above.summary.warning.find("exceeds noh-bathe's stable step"), std::string::npos)
      << above.summary.warning;
  EXPECT_LT(above.summary.steps, above.summary.planned_steps);

  // A consistent mass certifies nothing (stable_dt 0) and warns of nothing.
  rod.mass = MassMatrix::consistent;
  rod.courant = 0.5;
  testing::Run consistent = testing::run(rod, NohBatheParams{});
  EXPECT_EQ(consistent.summary.stable_dt, 0.0);
  EXPECT_TRUE(consistent.summary.warning.empty());
}

// Steps `system` from `s`, recording (as the header states) every sample's multipliers with the
// gap at the next sub-step t + Δt + pΔt, computed here as u + pΔt·v + (pΔt)²/2·a, and every
// sub-step's with the gap at the sample t + Δt; and that the sample's own gap holds.
SignoriniRecord step_scene(const SecondOrderSystem& system, State s, double dt, long steps,
                           double p = 0.54) {
  s.a = consistent_acceleration(system, s);
  NohBatheExplicit stepper;
  EXPECT_TRUE(stepper.initialize(system, noh_bathe_coefficients({.p = p}), dt, s));
  SignoriniRecord record;
  State ahead;
  for (long i = 0; i < steps; ++i) {
    stepper.step(system, s);
    ahead = stepper.substep_state();
    ahead.u = s.u;  // the sub-step's multipliers act on the sample's displacement
    record_signorini(system, ahead, record);
    ahead = s;
    ahead.u = s.u + (p * dt) * s.v + (0.5 * p * p * dt * dt) * s.a;
    record_signorini(system, ahead, record);
    // The sub-step's own displacement (fixed by the previous sample's multipliers).
    ahead = stepper.substep_state();
    ahead.lambda = ahead.far_lambda = 0.0;
    ahead.multipliers.setZero();
    record_signorini(system, ahead, record);
  }
  return record;
}

TEST(NohBathe, SignoriniConditionsHoldAtEverySampleAndSubStepOfThePapersRod) {
  const RodScene rod;
  const AssembledScene scene = assemble(rod);
  for (const double p : {0.5, 0.54, 0.8}) {
    expect_signorini(
        step_scene(scene.system, initial_state(scene, 0), scene.dt, scene.step_count, p), rod.gap,
        100);
  }
  const testing::Run run = testing::run(rod, NohBatheParams{});
  EXPECT_EQ(run.summary.status, RunStatus::ok) << run.summary.message;
  EXPECT_EQ(run.summary.steps, run.summary.planned_steps);
  for (std::size_t i = 0; i < run.trace.pressure.size(); ++i) {
    ASSERT_GE(run.trace.pressure[i], 0.0) << i;
    ASSERT_LE(run.trace.displacement[i], rod.gap) << i;
  }
  EXPECT_GT(*std::max_element(run.trace.pressure.begin(), run.trace.pressure.end()), 0.0);
  // A sweep runs it in the rod's batched kernel, bit for bit (tests/batched_explicit_test.cpp).
  EXPECT_TRUE(batchable(rod, NohBatheParams{}, RunOptions{}));
  // Skipping the rigid free flight starts the method later from the same rigid motion.
  const testing::Run skipped = testing::run(rod, NohBatheParams{}, RunOptions{});
  EXPECT_LT(testing::max_abs_difference(skipped.trace.pressure, run.trace.pressure),
            1e-6 * *std::max_element(run.trace.pressure.begin(), run.trace.pressure.end()));
}

TEST(NohBathe, SignoriniConditionsHoldBetweenTwoWallsAndInASceneOfBodies) {
  RodScene rod;
  rod.far_gap = 0.005;
  rod.t_end = 6e-4;  // the rod leaves the main wall at about 3.8e-4 s and reaches the far one
  const AssembledScene two_walls = assemble(rod);
  ASSERT_TRUE(two_walls.system.has_far_contact());
  const SignoriniRecord walls =
      step_scene(two_walls.system, initial_state(two_walls, 0), two_walls.dt, two_walls.step_count);
  expect_signorini(walls, rod.gap, 100);
  SimulationWorkspace ws;
  const RunSummary between = simulate(two_walls, NohBatheParams{}, RunOptions{}, ws);
  EXPECT_EQ(between.status, RunStatus::ok) << between.message;
  EXPECT_LE(between.max_penetration, 0.0);
  EXPECT_GT(*std::max_element(ws.trace.far_pressure.begin(), ws.trace.far_pressure.end()), 0.0);

  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  const AssembledScene scene = assemble(bodies);
  ASSERT_EQ(scene.system.constraints.size(), 2u);
  expect_signorini(step_scene(scene.system, initial_state(scene, 2), scene.dt, scene.step_count),
                   0.01, 100);
  const RunSummary summary = simulate(scene, NohBatheParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12 * 0.01);
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// A model of sparse matrices runs (the shipped block; the sparse stepper's checks are
// tests/sparse_explicit_test.cpp, the contact laws' tests/explicit_stage_contact_test.cpp).
TEST(NohBathe, RunsOnAModelOfSparseMatrices) {
  SimulationWorkspace ws;
  const Simulation block = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*block.model());
  ASSERT_TRUE(scene.sparse);
  const RunSummary summary = simulate(scene, NohBatheParams{}, RunOptions{}, ws);
  EXPECT_EQ(summary.status, RunStatus::ok) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12);
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// The registry: p by name and value, [½, 1); reported back with the derived q's and Ω_crit;
// another method's key refused; a reference of another p is another reference.
TEST(NohBathe, RegistryEntryAndRangeOfP) {
  for (const double p :
       {0.0, 0.3, 0.4999, 1.0, 1.5, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const auto e = validate(NohBatheParams{.p = p});
    ASSERT_TRUE(e) << p;
    EXPECT_EQ(e->field, "p");
    EXPECT_EQ(e->value, format_value(p));
    EXPECT_EQ(e->constraint,
              "must lie in [0.5, 1) (below 0.5 the scheme is unstable for every time step; 1 is "
              "excluded)");
  }
  for (const double p : {0.5, 0.54, 0.9, 0.999}) EXPECT_FALSE(validate(NohBatheParams{.p = p}));
  EXPECT_EQ(std::get<NohBatheParams>(default_params(MethodKind::noh_bathe)).p, 0.54);
  EXPECT_EQ(std::string(to_string(MethodKind::noh_bathe)), "noh-bathe");

  MethodArguments given;
  given.set("p", 0.6);
  const auto built = build_method(MethodKind::noh_bathe, given);
  ASSERT_TRUE(std::holds_alternative<MethodParams>(built));
  const MethodParams& params = std::get<MethodParams>(built);
  EXPECT_EQ(std::get<NohBatheParams>(params).p, 0.6);
  EXPECT_EQ(reported_value(params, "p"), 0.6);
  EXPECT_EQ(reported_value(params, "omega_crit"), noh_bathe_critical_omega(0.6));
  EXPECT_EQ(reported_value(params, "q1"), noh_bathe_coefficients({.p = 0.6}).q1);
  EXPECT_EQ(methods_taking("p"), "noh-bathe|kim-explicit");
  const auto refused = std::get<ParameterError>(build_method(MethodKind::houbolt, given));
  EXPECT_EQ(refused.constraint,
            "is not a parameter of method houbolt (it applies to noh-bathe|kim-explicit)");
  MethodArguments theta;
  theta.set("theta", 1.4);
  EXPECT_EQ(std::get<ParameterError>(build_method(MethodKind::noh_bathe, theta)).constraint,
            "is not a parameter of method noh-bathe (it applies to wilson-theta)");

  ReferenceOptions a, b;
  a.method = NohBatheParams{.p = 0.54};
  b.method = NohBatheParams{.p = 0.6};
  EXPECT_FALSE(a == b);
  b.method = NohBatheParams{.p = 0.54};
  EXPECT_TRUE(a == b);
}

// The command line: a bad p exits 2 naming --p and its value; a good one runs and reports it.
TEST(NohBathe, CommandLine) {
  const testing::CommandOutput bad = testing::run_impactid("simulate --method noh-bathe --p 0.4");
  EXPECT_EQ(bad.status, 2) << bad.text;
  EXPECT_NE(bad.text.find("--p = 0.4: must lie in [0.5, 1)"), std::string::npos) << bad.text;
  const testing::CommandOutput other = testing::run_impactid("simulate --method hht --p 0.6");
  EXPECT_EQ(other.status, 2) << other.text;
  EXPECT_NE(other.text.find("is not a parameter of method hht (it applies to "
                            "noh-bathe|kim-explicit)"),
            std::string::npos)
      << other.text;
  const testing::CommandOutput ok =
      testing::run_impactid("simulate --method noh-bathe --p 0.6 --json");
  EXPECT_EQ(ok.status, 0) << ok.text;
  EXPECT_NE(ok.text.find("\"p\":0.6"), std::string::npos) << ok.text;
  EXPECT_NE(ok.text.find("\"status\":\"ok\""), std::string::npos) << ok.text;
  const testing::CommandOutput methods = testing::run_impactid("methods");
  EXPECT_EQ(methods.status, 0);
  EXPECT_NE(methods.text.find("noh-bathe\n  Noh-Bathe explicit"), std::string::npos);
}

}  // namespace
}  // namespace impactid
