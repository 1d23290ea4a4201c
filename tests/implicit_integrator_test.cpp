// The implicit kernel shared by backward Euler, Newmark, HHT-α and generalized-α: measured
// convergence orders against the exact modal solution, the discrete equation of motion it claims
// to solve (checked with dense matrices), the contact complementarity, and restartability.
#include "core/methods/implicit_integrator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace impactid {
namespace {

using testing::dense_mode;
using testing::energy_norm_error;
using testing::free_rod;
using testing::make_state;
using testing::observed_orders;
using testing::run_implicit;

// The exact reference of the order tests must itself be right: the dense generalized eigensolver
// against the closed form ω₁ = (2c/h)·sin(π/(2n)) of the lumped free-free chain.
TEST(FreeRodReference, DenseFirstModeMatchesClosedForm) {
  for (int n : {4, 10, 25}) {
    const SecondOrderSystem system = free_rod(n);
    const double closed_form = 2.0 * n * std::sin(std::numbers::pi / (2.0 * n));  // c = 1, h = 1/n
    EXPECT_NEAR(dense_mode(system, 0).omega, 0.0, 1e-6) << n;  // rigid mode
    EXPECT_NEAR(dense_mode(system, 1).omega, closed_form, 1e-12 * closed_form) << n;
    // Highest mode of the lumped chain: 2c/h·sin(π·n/(2n)) = 2n.
    EXPECT_NEAR(dense_mode(system, n).omega, 2.0 * n, 1e-12 * 2.0 * n) << n;
  }
}

struct OrderCase {
  std::string name;
  MethodParams method;
  double expected_order;
};
void PrintTo(const OrderCase& c, std::ostream* os) { *os << c.name; }

// Relative energy-norm errors at T = 1 for Δt = T/40, T/80, …, T/640, starting from the first
// elastic mode displaced (so a₀ = −ω²φ ≠ 0): exact u(t) = φ·cos(ωt).
std::vector<double> mode_errors(const MethodParams& method) {
  const SecondOrderSystem system = free_rod(10);
  const testing::Mode mode = dense_mode(system, 1);
  const double t_end = 1.0;
  std::vector<double> errors;
  for (long steps = 40; steps <= 640; steps *= 2) {
    const State end =
        run_implicit(system, implicit_coefficients(method), t_end / steps, steps,
                     make_state(mode.phi, Eigen::VectorXd::Zero(mode.phi.size())));
    const Eigen::VectorXd u_exact = mode.phi * std::cos(mode.omega * t_end);
    const Eigen::VectorXd v_exact = -mode.omega * mode.phi * std::sin(mode.omega * t_end);
    errors.push_back(energy_norm_error(system, mode.omega, end.u - u_exact, end.v - v_exact) /
                     mode.omega);
  }
  return errors;
}

class ImplicitOrder : public ::testing::TestWithParam<OrderCase> {};

// Order of accuracy is the defining property of each method (paper sec. 2): halve Δt, measure.
TEST_P(ImplicitOrder, MeasuredOrderMatchesTheory) {
  const OrderCase& c = GetParam();
  const std::vector<double> errors = mode_errors(c.method);
  const std::vector<double> orders = observed_orders(errors);
  for (double e : errors) ASSERT_TRUE(std::isfinite(e)) << c.name;
  EXPECT_LT(errors.back(), 0.05) << c.name << ": not in the asymptotic range";
  // The last two ratios are in the asymptotic range.
  for (std::size_t k = orders.size() - 2; k < orders.size(); ++k) {
    EXPECT_NEAR(orders[k], c.expected_order, 0.12)
        << c.name << ": Δt = T/" << (40 << k) << " → T/" << (80 << k) << ", errors "
        << errors[k] << " → " << errors[k + 1];
  }
}

INSTANTIATE_TEST_SUITE_P(
    Methods, ImplicitOrder,
    ::testing::Values(OrderCase{"trapezoidal", NewmarkParams{.delta = 0.0}, 2.0},
                      OrderCase{"newmark_delta_0_3", NewmarkParams{.delta = 0.3}, 1.0},
                      OrderCase{"backward_euler", BackwardEulerParams{}, 1.0},
                      OrderCase{"hht_alpha_m0_2", HhtParams{.alpha = -0.2}, 2.0},
                      OrderCase{"hht_alpha_m0_3_weighted",
                                HhtParams{.alpha = -0.3, .contact = ContactWeighting::weighted},
                                2.0},
                      OrderCase{"hht_alpha_m0_3_delta_0_45",
                                HhtParams{.alpha = -0.3, .delta = 0.45}, 1.0},
                      OrderCase{"generalized_alpha", GeneralizedAlphaParams{}, 2.0},
                      OrderCase{"generalized_alpha_rho_0", GeneralizedAlphaParams{.rho_inf = 0.0},
                                2.0}),
    [](const ::testing::TestParamInfo<OrderCase>& info) { return info.param.name; });

// A damped, consistent-mass rod with contact: the general case of the kernel.
struct ContactProblem {
  SecondOrderSystem system;
  double dt;
  State initial;
};
ContactProblem contact_problem(double gap) {
  SecondOrderSystem system = free_rod(6, MassMatrix::consistent);
  system.damping = system.mass.combined(0.3, system.stiffness, 0.002);
  system.gap = gap;
  const Eigen::Index n = system.size();
  Eigen::VectorXd u(n), v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = static_cast<double>(i) / (n - 1);
    u[i] = 0.01 * std::sin(2.0 * x);  // a stressed rod, so a₀ is not zero
    v[i] = 1.0 + 0.2 * x;
  }
  return {system, 0.01, make_state(u, v)};
}

// The kernel must solve exactly the one-step relations documented in method.hpp:
//   u₁ = u₀ + Δt·v₀ + Δt²·(b0·a₀ + b1·a₁),  v₁ = v₀ + Δt·(g0·a₀ + g1·a₁),
//   (1−α_m)·M·a₁ + α_m·M·a₀ + (1−α_f)·(C·v₁ + K·u₁) + α_f·(C·v₀ + K·u₀) + e_c·(w·λ₁ + (1−w)·λ₀) = 0
// with u_c = gap, λ₁ > 0 when the contact closes. Checked with dense matrices.
TEST(ImplicitIntegrator, StepSolvesTheDocumentedRelationsWithContact) {
  const std::vector<std::pair<std::string, MethodParams>> methods = {
      {"backward-euler", BackwardEulerParams{}},
      {"newmark", NewmarkParams{.delta = 0.3}},
      {"hht", HhtParams{.alpha = -0.3}},
      {"hht-weighted", HhtParams{.alpha = -0.3, .contact = ContactWeighting::weighted}},
      {"generalized-alpha", GeneralizedAlphaParams{.rho_inf = 0.6}},
      {"generalized-alpha-weighted",
       GeneralizedAlphaParams{.rho_inf = 0.6, .contact = ContactWeighting::weighted}},
  };
  for (const auto& [name, method] : methods) {
    // gap small enough that the first step closes the contact.
    ContactProblem p = contact_problem(0.012);
    const ImplicitCoefficients c = implicit_coefficients(method);
    const Eigen::MatrixXd m = p.system.mass.dense(), k = p.system.stiffness.dense(),
                          cd = p.system.damping.dense();
    const Eigen::Index contact = p.system.contact_dof;
    ImplicitIntegrator integrator;
    ASSERT_TRUE(integrator.initialize(p.system, c, p.dt)) << name;
    State s = p.initial;
    s.a = consistent_acceleration(p.system, s);
    for (int step = 0; step < 6; ++step) {
      const State s0 = s;
      const bool active = integrator.step(p.system, s);
      if (step == 0) {
        ASSERT_TRUE(active) << name << ": the first step must close the contact";
      }
      // Complementarity: either on the wall with a compressive force, or free with none.
      if (active) {
        EXPECT_GT(s.lambda, 0.0) << name;
        EXPECT_EQ(s.u[contact], p.system.gap) << name;
      } else {
        EXPECT_EQ(s.lambda, 0.0) << name;
        EXPECT_LE(s.u[contact], p.system.gap) << name;
      }
      EXPECT_NEAR(s.t, s0.t + p.dt, 1e-15);
      const double dt = p.dt;
      const Eigen::VectorXd u_expected = s0.u + dt * s0.v + dt * dt * (c.b0 * s0.a + c.b1 * s.a);
      const Eigen::VectorXd v_expected = s0.v + dt * (c.g0 * s0.a + c.g1 * s.a);
      EXPECT_LE((s.u - u_expected).lpNorm<Eigen::Infinity>(), 1e-14) << name;
      EXPECT_LE((s.v - v_expected).lpNorm<Eigen::Infinity>(), 1e-13) << name;
      Eigen::VectorXd residual = (1 - c.alpha_m) * m * s.a + c.alpha_m * m * s0.a +
                                 (1 - c.alpha_f) * (cd * s.v + k * s.u) +
                                 c.alpha_f * (cd * s0.v + k * s0.u);
      residual[contact] += c.contact_weight * s.lambda + (1 - c.contact_weight) * s0.lambda;
      const double scale = (m * s.a).norm() + (k * s.u).norm() + s.lambda;
      EXPECT_LE(residual.norm(), 1e-12 * scale) << name << " step " << step;
    }
  }
}

// Far from the wall the contact must stay open: λ = 0, and the relations hold without it.
TEST(ImplicitIntegrator, NoContactForceAwayFromTheWall) {
  ContactProblem p = contact_problem(10.0);
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(p.system, implicit_coefficients(HhtParams{}), p.dt));
  State s = p.initial;
  s.a = consistent_acceleration(p.system, s);
  EXPECT_FALSE(integrator.step(p.system, s));
  EXPECT_EQ(s.lambda, 0.0);
  EXPECT_LT(s.u[p.system.contact_dof], p.system.gap);
}

// Unilateral contact: a node on the wall moving away must be released (no tensile λ).
TEST(ImplicitIntegrator, TensileContactForceIsReleased) {
  ContactProblem p = contact_problem(0.0);
  p.initial.u.setZero();
  p.initial.v.setConstant(-1.0);  // the whole rod leaves the wall
  ImplicitIntegrator integrator;
  ASSERT_TRUE(integrator.initialize(p.system, implicit_coefficients(NewmarkParams{}), p.dt));
  State s = p.initial;
  s.lambda = 0.5;  // a contact force left over from the previous step
  s.a = consistent_acceleration(p.system, s);
  EXPECT_FALSE(integrator.step(p.system, s));
  EXPECT_EQ(s.lambda, 0.0);
  EXPECT_LT(s.u[p.system.contact_dof], 0.0);
}

// M·a = −K·u − C·v − e_c·λ, against a dense solve.
TEST(ImplicitIntegrator, ConsistentAccelerationMatchesDenseSolve) {
  ContactProblem p = contact_problem(0.0);
  p.initial.lambda = 0.7;
  const Eigen::VectorXd a = consistent_acceleration(p.system, p.initial);
  Eigen::VectorXd rhs =
      -p.system.stiffness.dense() * p.initial.u - p.system.damping.dense() * p.initial.v;
  rhs[p.system.contact_dof] -= 0.7;
  const Eigen::VectorXd reference = p.system.mass.dense().ldlt().solve(rhs);
  EXPECT_LE((a - reference).norm(), 1e-12 * reference.norm());
}

// A non-positive mass makes the effective matrix singular: reported, not divided by zero.
TEST(ImplicitIntegrator, SingularEffectiveMatrixIsReported) {
  SecondOrderSystem system = free_rod(3);
  system.mass.diag.setZero();
  system.stiffness = Tridiagonal::zero(4);
  ImplicitIntegrator integrator;
  EXPECT_FALSE(integrator.initialize(system, implicit_coefficients(NewmarkParams{}), 0.1));
}

// State is a value (habit 4): a run split in two, resumed by a fresh integrator from a copy of
// the state, equals one continuous run bit for bit.
TEST(ImplicitIntegrator, SplitRunEqualsContinuousRun) {
  ContactProblem p = contact_problem(0.012);
  const ImplicitCoefficients c = implicit_coefficients(GeneralizedAlphaParams{});
  ImplicitIntegrator one;
  ASSERT_TRUE(one.initialize(p.system, c, p.dt));
  State continuous = p.initial;
  continuous.a = consistent_acceleration(p.system, continuous);
  State split = continuous;
  for (int i = 0; i < 40; ++i) one.step(p.system, continuous);

  ImplicitIntegrator first, second;
  ASSERT_TRUE(first.initialize(p.system, c, p.dt));
  for (int i = 0; i < 17; ++i) first.step(p.system, split);
  const State restart = split;  // copy, then continue with another integrator
  State resumed = restart;
  ASSERT_TRUE(second.initialize(p.system, c, p.dt));
  for (int i = 17; i < 40; ++i) second.step(p.system, resumed);
  EXPECT_EQ(resumed.u, continuous.u);
  EXPECT_EQ(resumed.v, continuous.v);
  EXPECT_EQ(resumed.a, continuous.a);
  EXPECT_EQ(resumed.lambda, continuous.lambda);
  EXPECT_EQ(resumed.t, continuous.t);
}

}  // namespace
}  // namespace impactid
