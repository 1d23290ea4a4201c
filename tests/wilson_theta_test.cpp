// Wilson-θ (core/methods/wilson_theta.hpp): second order measured by halving Δt against the exact
// modal solution, with and without damping, for several θ; every step is Wilson's update from an
// equilibrium at t + θΔt (dense matrices); the spectral analysis against closed forms (period
// error (6θ² − 6θ + 1)/24·Ω², ρ∞ the largest root of the limit's cubic, −1 at θ = (1 + √3)/2),
// unconditional stability from (1 + √3)/2 on and not below; a free mass stopped by the wall at
// t + Δt leaves at up to twice its speed (why it chatters); the Signorini conditions at every
// sample t + Δt (not at t + θΔt) on the paper's rod, between two walls, on a scene of bodies and
// on sparse models; never batched.
#include "core/methods/wilson_theta.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>
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

using TridiagonalWilson = WilsonTheta<ImplicitIntegrator, SecondOrderSystem>;

std::vector<double> mode_errors(double theta, double a1) {
  const SecondOrderSystem system = damped_free_rod(a1);
  const testing::Mode mode = dense_mode(system, 1);
  const ModalExact exact{mode.omega, 0.5 * a1 * mode.omega};
  std::vector<double> errors;
  for (long steps = 40; steps <= 640; steps *= 2) {
    State s = make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size()));
    s.a = consistent_acceleration(system, s);
    TridiagonalWilson stepper;
    EXPECT_TRUE(
        stepper.initialize(system, wilson_theta_coefficients({.theta = theta}), 1.0 / steps));
    for (long i = 0; i < steps; ++i) stepper.step(system, s);
    errors.push_back(energy_norm_error(system, mode.omega, s.u - mode.phi * exact.q(1.0),
                                       s.v - mode.phi * exact.dq(1.0)) /
                     mode.omega);
  }
  return errors;
}

TEST(WilsonTheta, IsSecondOrderWithAndWithoutDamping) {
  for (const double theta : {kWilsonThetaMinimum, 1.4, 2.0}) {
    for (const double a1 : {0.0, 0.02}) {
      const std::vector<double> errors = mode_errors(theta, a1);
      const std::vector<double> orders = observed_orders(errors);
      EXPECT_LT(errors.back(), 1e-3) << theta << " " << a1;
      for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
        EXPECT_NEAR(orders[k], 2.0, 0.1) << theta << " " << a1 << " " << k;
      }
    }
  }
}

// The extended step is in equilibrium at t + θΔt (M·a_θ + C·v_θ + K·u_θ = 0 at the linear-
// acceleration update over θΔt), and the state at t + Δt is Wilson's update from it, each
// written here as the paper writes it.
TEST(WilsonTheta, EachStepIsWilsonsUpdateFromAnEquilibriumAtThetaDt) {
  const SecondOrderSystem system = damped_free_rod(0.02);
  const testing::Mode mode = dense_mode(system, 2);
  const double dt = 0.03, theta = 1.4, tau = theta * dt;
  const Eigen::MatrixXd m = system.mass.dense(), c = system.damping.dense(),
                        k = system.stiffness.dense();
  State s = make_state(mode.phi, 0.7 * mode.omega * mode.phi);
  s.a = consistent_acceleration(system, s);
  TridiagonalWilson stepper;
  ASSERT_TRUE(stepper.initialize(system, wilson_theta_coefficients({.theta = theta}), dt));
  const double tolerance = 1e-11 * mode.omega * mode.omega * mode.phi.norm();  // of |a|
  for (int i = 0; i < 10; ++i) {
    const State before = s;
    stepper.step(system, s);
    const State& x = stepper.extended_state();
    EXPECT_LT((m * x.a + c * x.v + k * x.u).norm(), tolerance) << i;
    EXPECT_LT((x.u - before.u - tau * before.v - tau * tau * (before.a / 3.0 + x.a / 6.0)).norm(),
              tolerance * tau * tau);
    EXPECT_LT((x.v - before.v - 0.5 * tau * (before.a + x.a)).norm(), tolerance * tau);
    EXPECT_LT((s.a - before.a - (x.a - before.a) / theta).norm(), tolerance) << i;
    EXPECT_LT((s.v - before.v - 0.5 * dt * (before.a + s.a)).norm(), tolerance * dt) << i;
    EXPECT_LT((s.u - before.u - dt * before.v - dt * dt * (2.0 * before.a + s.a) / 6.0).norm(),
              tolerance * dt * dt)
        << i;
    EXPECT_NEAR(s.t, before.t + dt, 1e-15);
  }
}

// The largest root modulus of the limit's characteristic polynomial (derived from the matrix of
// core/methods/wilson_theta.hpp's update with Ω → ∞, by hand):
//   θ³λ³ + (1 + 3θ + 3θ² − 3θ³)λ² + (3θ³ − 6θ² + 4)λ − (θ − 1)³ = 0.
// At λ = −1 it is −2(4θ³ − 6θ² + 1) = −2(2θ − 1)(2θ² − 2θ − 1), zero at θ = (1 + √3)/2.
double limit_rho(double theta) {
  const double t2 = theta * theta, t3 = t2 * theta;
  Eigen::Matrix3d companion;
  companion << -(1.0 + 3.0 * theta + 3.0 * t2 - 3.0 * t3) / t3, -(3.0 * t3 - 6.0 * t2 + 4.0) / t3,
      std::pow(theta - 1.0, 3) / t3, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0;
  return testing::spectral_radius_of(companion);
}

TEST(WilsonTheta, SpectralPropertiesAgainstClosedForms) {
  for (const double theta : {kWilsonThetaMinimum, 1.4, 1.5, 2.0, 3.0}) {
    const MethodParams method = WilsonThetaParams{.theta = theta};
    const double c = (6.0 * theta * theta - 6.0 * theta + 1.0) / 24.0;
    // Richardson's extrapolation loses digits as c grows (measured 1.1e-9 relative at θ = 3).
    EXPECT_NEAR(period_error_coefficient(method), c, 1e-8 * c) << theta;
    EXPECT_NEAR(high_frequency_spectral_radius(method), limit_rho(theta), 1e-13) << theta;
    EXPECT_NEAR(spectral_properties(method, 1e8).spectral_radius, limit_rho(theta), 1e-7) << theta;
    // ξ̄ = θ(θ − 1)(2θ − 1)/12·Ω³ to leading order (from the same series as the period error).
    EXPECT_NEAR(spectral_properties(method, 0.01).damping_ratio /
                    (theta * (theta - 1.0) * (2.0 * theta - 1.0) / 12.0 * 1e-6),
                1.0, 1e-2)
        << theta;
    EXPECT_TRUE(is_stable(method, 1e6)) << theta;
  }
  EXPECT_NEAR(high_frequency_spectral_radius(WilsonThetaParams{}), 0.7784422200924646, 1e-13);
  EXPECT_NEAR(limit_rho(kWilsonThetaMinimum), 1.0, 1e-12);
  // Below the limit the high frequencies grow: ρ∞ > 1.
  for (const double theta : {1.36, 1.365}) EXPECT_GT(limit_rho(theta), 1.0) << theta;
  // The same matrix as stepping a one-dof oscillator (ω = 1, Δt = Ω) from the three unit states
  // (u, Δt·v, Δt²·a).
  SecondOrderSystem oscillator;
  oscillator.mass = Tridiagonal::zero(1);
  oscillator.mass.diag[0] = 1.0;
  oscillator.stiffness = oscillator.mass;
  oscillator.damping = Tridiagonal::zero(1);
  for (const double omega : {0.2, 1.5, 30.0}) {
    const Eigen::MatrixXd expected = amplification_matrix(WilsonThetaParams{}, omega);
    TridiagonalWilson stepper;
    ASSERT_TRUE(stepper.initialize(oscillator, wilson_theta_coefficients({}), omega));
    for (int j = 0; j < 3; ++j) {
      State s = make_state(Eigen::VectorXd::Constant(1, j == 0 ? 1.0 : 0.0),
                           Eigen::VectorXd::Constant(1, j == 1 ? 1.0 / omega : 0.0));
      s.a = Eigen::VectorXd::Constant(1, j == 2 ? 1.0 / (omega * omega) : 0.0);
      stepper.step(oscillator, s);
      const Eigen::Vector3d column(s.u[0], omega * s.v[0], omega * omega * s.a[0]);
      EXPECT_LT((column - expected.col(j)).norm(), 1e-13) << omega << " " << j;
    }
  }
}

// The validation's bound is the stability limit, measured on both sides: at (1 + √3)/2 the scan
// up to Ω = 1e6 stays at ρ <= 1; just below, which validate() refuses (so the spectral analysis
// does not run it), a one-dof oscillator stepped at Ω = 1e4 (the stepper does not validate)
// grows, and at the limit it does not.
TEST(WilsonTheta, StabilityLimitIsOneHalfOfOnePlusRootThree) {
  EXPECT_TRUE(is_stable(WilsonThetaParams{.theta = kWilsonThetaMinimum}, 1e6));
  EXPECT_TRUE(validate(WilsonThetaParams{.theta = 1.36}));
  SecondOrderSystem oscillator;
  oscillator.mass = Tridiagonal::zero(1);
  oscillator.mass.diag[0] = 1.0;
  oscillator.stiffness = oscillator.mass;
  oscillator.damping = Tridiagonal::zero(1);
  for (const double theta : {1.36, kWilsonThetaMinimum}) {
    TridiagonalWilson stepper;
    ASSERT_TRUE(stepper.initialize(oscillator, wilson_theta_coefficients({.theta = theta}), 1e4));
    State s = make_state(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 0.0));
    s.a = consistent_acceleration(oscillator, s);
    // The scaled state (u, Δt·v, Δt²·a) of the amplification matrix.
    const auto size = [](const State& x) {
      return std::abs(x.u[0]) + std::abs(1e4 * x.v[0]) + std::abs(1e8 * x.a[0]);
    };
    const double initial = size(s);
    for (int i = 0; i < 400; ++i) stepper.step(oscillator, s);
    if (theta < kWilsonThetaMinimum) {
      EXPECT_GT(size(s) / initial, 1e4) << theta;  // ρ∞ = 1.036: 1.036^400 ≈ 1.3e6
    } else {
      EXPECT_LT(size(s) / initial, 10.0) << theta;
    }
  }
}

// A mass without spring (m = 1) flying at v0 = 1 onto a wall 1 ahead.
SecondOrderSystem free_mass_on_a_wall() {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(1);
  system.mass.diag[0] = 1.0;
  system.stiffness = Tridiagonal::zero(1);
  system.damping = Tridiagonal::zero(1);
  system.contact_dof = 0;
  system.gap = 1.0;
  return system;
}

// Why Wilson-θ chatters on a wall with the contact at the samples: from t to t + Δt its update is
// the linear-acceleration step, u_{n+1} = u_n + Δt·v_n + Δt²(2a_n + a_{n+1})/6,
// v_{n+1} = v_n + Δt(a_n + a_{n+1})/2, so the force that puts a node on the wall at t + Δt
// changes its velocity by 3/Δt times the displacement it takes away (γ/β = 3, against 2 for the
// trapezoidal rule). A free mass arriving at v_n with the wall δ = gap − u_n ahead leaves at
// v_{n+1} = −2v_n + 3δ/Δt, whatever θ: up to twice as fast as it came.
TEST(WilsonTheta, AFreeMassLeavesTheWallUpToTwiceAsFastAsItCame) {
  const SecondOrderSystem system = free_mass_on_a_wall();
  for (const double theta : {kWilsonThetaMinimum, 1.4, 2.0, 3.0}) {
    for (const double dt : {0.33, 0.3, 0.26}) {
      State s = make_state(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
      s.a = consistent_acceleration(system, s);
      TridiagonalWilson stepper;
      ASSERT_TRUE(stepper.initialize(system, wilson_theta_coefficients({.theta = theta}), dt));
      while (s.u[0] + dt * s.v[0] <= system.gap) {
        stepper.step(system, s);
        ASSERT_EQ(s.lambda, 0.0);
      }
      const double u = s.u[0], v = s.v[0];
      stepper.step(system, s);
      EXPECT_GT(s.lambda, 0.0);
      EXPECT_EQ(s.u[0], system.gap);
      EXPECT_NEAR(s.v[0], -2.0 * v + 3.0 * (system.gap - u) / dt, 1e-12) << theta << " " << dt;
    }
  }
}

template <class Integrator, class System>
SignoriniRecord step_scene(const System& system, State s, double dt, long steps, double theta = 1.4,
                           double* largest_shift = nullptr) {
  s.a = consistent_acceleration(system, s);
  WilsonTheta<Integrator, System> stepper;
  EXPECT_TRUE(stepper.initialize(system, wilson_theta_coefficients({.theta = theta}), dt));
  SignoriniRecord record;
  for (long i = 0; i < steps; ++i) {
    stepper.step(system, s);
    record_signorini(system, s, record);
    if constexpr (std::is_same_v<System, SecondOrderSystem>) {
      // How far the extended step's contact node is from the wall while it pushes: where the
      // constraint would have been enforced without the shift.
      if (largest_shift && s.lambda > 0.0) {
        *largest_shift = std::max(
            *largest_shift, std::abs(stepper.extended_state().u[system.contact_dof] - system.gap));
      }
    }
  }
  return record;
}

// The paper's rod: at every sample t + Δt, λ >= 0, the node not beyond the wall and on it where
// λ > 0, for θ at the limit, the default and 2; the extended step's node is then off the wall
// (the constraint really is enforced at t + Δt); simulate() agrees; the rod's batched kernel
// takes it (its lanes equal simulate(): tests/batched_simulation_test.cpp).
TEST(WilsonTheta, SignoriniConditionsHoldAtEverySampleOfThePapersRod) {
  const RodScene rod;
  const AssembledScene scene = assemble(rod);
  for (const double theta : {kWilsonThetaMinimum, 1.4, 2.0}) {
    double shift = 0.0;
    expect_signorini(step_scene<ImplicitIntegrator>(scene.system, initial_state(scene, 0), scene.dt,
                                                    scene.step_count, theta, &shift),
                     rod.gap, 20);
    EXPECT_GT(shift, 1e-3 * rod.gap) << theta;
  }
  const testing::Run run = testing::run(rod, WilsonThetaParams{});
  EXPECT_NE(run.summary.status, RunStatus::failed) << run.summary.message;
  for (std::size_t i = 0; i < run.trace.pressure.size(); ++i) {
    if (std::isnan(run.trace.pressure[i])) break;  // an unstable run's end
    ASSERT_GE(run.trace.pressure[i], 0.0) << i;
    ASSERT_LE(run.trace.displacement[i], rod.gap * (1.0 + 1e-12)) << i;
  }
  EXPECT_TRUE(batchable(rod, WilsonThetaParams{}, RunOptions{}));
}

TEST(WilsonTheta, SignoriniConditionsHoldBetweenTwoWallsAndInAsceneOfBodies) {
  RodScene rod;
  rod.far_gap = 0.005;
  rod.t_end = 3e-4;
  const AssembledScene two_walls = assemble(rod);
  ASSERT_TRUE(two_walls.system.has_far_contact());
  expect_signorini(step_scene<ImplicitIntegrator>(two_walls.system, initial_state(two_walls, 0),
                                                  two_walls.dt, two_walls.step_count),
                   rod.gap, 20);

  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  const AssembledScene scene = assemble(bodies);
  ASSERT_EQ(scene.system.constraints.size(), 2u);
  expect_signorini(step_scene<ImplicitIntegrator>(scene.system, initial_state(scene, 2), scene.dt,
                                                  scene.step_count),
                   0.01, 20);
  SimulationWorkspace ws;
  const RunSummary summary =
      simulate(scene, WilsonThetaParams{}, RunOptions{.energy_growth_limit = 1e3}, ws);
  EXPECT_NE(summary.status, RunStatus::failed) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-12 * 0.01);
  EXPECT_FALSE(chain_batchable(scene, WilsonThetaParams{}, RunOptions{}));
  EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(ws.trace));
}

// Steps Wilson-θ under a contact law and checks at every sample t + Δt: λ >= 0, and for the
// penalty λ = k·max(0, g(u_{n+1})), the spring of the sample's own penetration (the extended
// step's spring is k/θ³, core/methods/wilson_theta.hpp). Returns the pushing (constraint, sample)
// pairs.
template <class Integrator, class System>
long check_law_at_samples(const System& system, State s, double dt, long steps,
                          const ContactPenalties& contact, double theta, double force_scale) {
  s.a = consistent_acceleration(system, s);
  WilsonTheta<Integrator, System> stepper;
  EXPECT_TRUE(stepper.initialize(system, wilson_theta_coefficients({.theta = theta}), dt, contact));
  long pushing = 0;
  const auto check = [&](double g, double lambda, double k, long i) {
    EXPECT_GE(lambda, 0.0) << i;
    if (contact.law == ContactLaw::penalty) {
      EXPECT_NEAR(lambda, k * std::max(0.0, g), 1e-9 * force_scale) << i;
    }
    pushing += lambda > 0.0;
  };
  for (long i = 0; i < steps; ++i) {
    stepper.step(system, s);
    for (std::size_t j = 0; j < system.constraints.size(); ++j) {
      check(testing::violation(system.constraints[j], s.u),
            s.multipliers[static_cast<Eigen::Index>(j)], contact.listed[j], i);
    }
    if constexpr (std::is_same_v<System, SecondOrderSystem>) {
      if (system.has_constraint_list()) continue;
      check(s.u[system.contact_dof] - system.gap, s.lambda, contact.main, i);
      if (system.has_far_contact()) {
        check(-system.far_gap - s.u[system.far_contact_dof], s.far_lambda, contact.far, i);
      }
    }
  }
  if (contact.law == ContactLaw::augmented_lagrangian) {
    EXPECT_GT(stepper.contact_iterations(), 0);
  }
  return pushing;
}

// Penalty and augmented Lagrangian where Wilson-θ enforces its constraint, at the samples: the
// penalty's λ is the spring k of the sample's penetration on the rod, between two walls, in a
// scene of bodies and on a sparse model, for θ at the limit, the default and 2.
TEST(WilsonTheta, PenaltyIsTheSpringOfTheSamplesPenetration) {
  const RodScene rod;
  const double rho_c_v0_area =
      rod.density * std::sqrt(rod.youngs_modulus / rod.density) * rod.velocity * rod.area;
  RodScene walls;
  walls.far_gap = 0.005;
  walls.t_end = 3e-4;
  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  bodies.t_end = 4e-4;
  std::vector<AssembledScene> scenes;
  scenes.push_back(assemble(rod));
  scenes.push_back(assemble(walls));
  scenes.push_back(assemble(bodies));
  for (const ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    const ContactTreatment treatment{.law = law, .penalty_factor = 3.0};
    for (const AssembledScene& scene : scenes) {
      const ContactPenalties contact = resolve_contact(treatment, scene.system);
      const auto m = static_cast<Eigen::Index>(scene.system.constraints.size());
      for (const double theta : {kWilsonThetaMinimum, 1.4, 2.0}) {
        SCOPED_TRACE(std::string(to_string(law)) + " theta " + std::to_string(theta) +
                     " constraints " + std::to_string(m));
        EXPECT_GT(check_law_at_samples<ImplicitIntegrator>(scene.system, initial_state(scene, m),
                                                           scene.dt, scene.step_count, contact,
                                                           theta, rho_c_v0_area),
                  20);
      }
    }
    const testing::SparseRodPair pair = testing::sparse_rod_pair();
    const RodSceneDerived d = derive(pair.rod);
    const ContactPenalties contact = resolve_contact(treatment, pair.sparse);
    SCOPED_TRACE(std::string(to_string(law)) + " sparse");
    EXPECT_GT(check_law_at_samples<SparseImplicitIntegrator>(
                  pair.sparse, pair.start, d.time_step, d.step_count, contact, 1.4, rho_c_v0_area),
              20);
  }
}

// As k grows the penalty approaches Lagrange's solution at first order in 1/k, as the
// single-step methods' do (tests/contact_treatment_test.cpp): each decade of k from 10⁴·E·A/h on
// divides the largest pressure difference by 10 (measured orders 0.998, 1.000), on the first 21
// steps of the contact: later Wilson-θ's chatter (the header) magnifies any difference (at
// 3e-5 s the factors 1e3 and 1e4 differ from Lagrange by 13 MPa alike). The augmented Lagrangian
// reaches Lagrange's pressures within its tolerance there (2e-8 MPa measured), and counts its
// iterations.
TEST(WilsonTheta, PenaltyConvergesToLagrangeAndTheAugmentedLagrangianReachesIt) {
  RodScene rod;
  rod.t_end = 2e-5;
  const double rho_c_v0 = rod.density * std::sqrt(rod.youngs_modulus / rod.density) * rod.velocity;
  const RunOptions base = testing::stepping_options(1e3);
  const testing::Run lagrange = testing::run(rod, WilsonThetaParams{}, base);
  ASSERT_EQ(lagrange.summary.status, RunStatus::ok) << lagrange.summary.message;
  std::vector<double> differences;
  for (const double factor : {1e4, 1e5, 1e6}) {
    RunOptions options = base;
    options.contact = {.law = ContactLaw::penalty, .penalty_factor = factor};
    const testing::Run r = testing::run(rod, WilsonThetaParams{}, options);
    ASSERT_EQ(r.summary.status, RunStatus::ok) << r.summary.message;
    EXPECT_GT(r.summary.max_penetration, 0.0);
    differences.push_back(testing::max_abs_difference(r.trace.pressure, lagrange.trace.pressure));
  }
  for (std::size_t i = 0; i + 1 < differences.size(); ++i) {
    EXPECT_NEAR(std::log10(differences[i] / differences[i + 1]), 1.0, 0.1) << i;
  }
  RunOptions options = base;
  options.contact = {.law = ContactLaw::augmented_lagrangian,
                     .penalty_factor = 10.0,
                     .augmented_tolerance = 1e-9,
                     .augmented_max_iterations = 1000};
  const testing::Run al = testing::run(rod, WilsonThetaParams{}, options);
  ASSERT_EQ(al.summary.status, RunStatus::ok) << al.summary.message;
  EXPECT_LT(testing::max_abs_difference(al.trace.pressure, lagrange.trace.pressure),
            1e-6 * rho_c_v0);
  EXPECT_GT(al.summary.contact_iterations, 0);
  EXPECT_EQ(al.summary.unconverged_contact_steps, 0);
}

TEST(WilsonTheta, SparseModelsKeepTheConditions) {
  const testing::SparseRodPair pair = testing::sparse_rod_pair();
  const RodScene& rod = pair.rod;
  const SecondOrderSystem& tri = pair.tridiagonal;
  const SparseSystem& sys = pair.sparse;
  const Eigen::Index n = tri.size();
  const RodSceneDerived d = derive(rod);
  State a = pair.start;
  State b = a;
  TridiagonalWilson x;
  WilsonTheta<SparseImplicitIntegrator, SparseSystem> y;
  ASSERT_TRUE(x.initialize(tri, wilson_theta_coefficients({}), d.time_step));
  ASSERT_TRUE(y.initialize(sys, wilson_theta_coefficients({}), d.time_step));
  // The same contact activity at every step; each impact of the chatter (below) multiplies the
  // round-off about fivefold (measured: 2e-18 at the first, 1.5e-10 relative 40 steps later).
  const long steps = static_cast<long>(d.impact_time / d.time_step) + 40;
  double worst = 0.0, largest = 0.0;
  for (long i = 0; i < steps; ++i) {
    x.step(tri, a);
    y.step(sys, b);
    ASSERT_EQ(a.multipliers[0] > 0.0, b.multipliers[0] > 0.0) << i;
    worst = std::max(worst, (a.u - b.u).lpNorm<Eigen::Infinity>());
    largest = std::max(largest, a.u.lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-9 * largest);
  State start = make_state(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(n, rod.velocity));
  start.multipliers = Eigen::VectorXd::Zero(1);
  expect_signorini(step_scene<SparseImplicitIntegrator>(sys, start, d.time_step, d.step_count),
                   rod.gap, 20);

  const Simulation block = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*block.model());
  ASSERT_TRUE(scene.sparse);
  SimulationWorkspace ws;
  const RunSummary summary =
      simulate(scene, WilsonThetaParams{}, RunOptions{.energy_growth_limit = 1e3}, ws);
  EXPECT_NE(summary.status, RunStatus::failed) << summary.message;
  EXPECT_LE(summary.max_penetration, 1e-9 * 0.001);
  for (const auto& contact : ws.trace.contact_pressure) {
    EXPECT_GE(*std::min_element(contact.begin(), contact.end()), 0.0);
  }
}

}  // namespace
}  // namespace impactid
