// The Noh–Bathe explicit scheme (core/methods/noh_bathe.hpp): its descriptor.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"p"};

MadeMethod make(const MethodArguments& given) {
  NohBatheParams p;
  if (const auto value = given.number("p")) p.p = *value;
  return p;
}

// p, then the velocity weights and the stability limit Ω_crit(p) (derived).
MethodValues values(const MethodParams& params) {
  const auto& p = std::get<NohBatheParams>(params);
  const NohBatheCoefficients c = noh_bathe_coefficients(p);
  return {{"p", p.p, false},
          {"q0", c.q0, true},
          {"q1", c.q1, true},
          {"q2", c.q2, true},
          {"omega_crit", noh_bathe_critical_omega(p.p), true}};
}

bool same(const MethodParams& a, const MethodParams& b) {
  return std::get<NohBatheParams>(a).p == std::get<NohBatheParams>(b).p;
}

// The Noh–Bathe explicit step (core/methods/noh_bathe.hpp without damping and contact) on
// x = (u, Δt·v, Δt²·a), composed from its two sub-steps row by row:
//   u_p = u + p·V + p²/2·A,                 A_p = −Ω²·u_p,   V_p = V + p/2·(A + A_p),
//   u₁ = u_p + (1−p)·V_p + (1−p)²/2·A_p,    A₁ = −Ω²·u₁,
//   V₁ = V_p + (1−p)·(q0·A + (½ + q1)·A_p + q2·A₁).
// Entries grow like Ω⁴, harmless within the explicit limit (Ω_crit <= 4).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> noh_bathe_amplification(const NohBatheCoefficients& c,
                                                    double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar p = c.p, r = 1 - p, q0 = c.q0, q1 = c.q1, q2 = c.q2, omega = omega_dt;
  const Scalar w2 = omega * omega, half = Scalar(1) / 2;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row u_p = e_u + p * e_v + (p * p / 2) * e_a;
  const Row a_p = -w2 * u_p;
  const Row v_p = e_v + (p / 2) * (e_a + a_p);
  const Row u1 = u_p + r * v_p + (r * r / 2) * a_p;
  const Row a1 = -w2 * u1;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u1;
  a.row(1) = v_p + r * (q0 * e_a + (half + q1) * a_p + q2 * a1);
  a.row(2) = a1;
  return a;
}

Eigen::MatrixXd amplification(const MethodParams& params, double omega_dt) {
  return noh_bathe_amplification<double>(noh_bathe_coefficients(std::get<NohBatheParams>(params)),
                                         omega_dt);
}

std::vector<SpectralEigenvalue> eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(
      noh_bathe_amplification<SpectralScalar>(
          noh_bathe_coefficients(std::get<NohBatheParams>(params)), omega_dt),
      omega_dt);
}

double stability_limit(const MethodParams& params) {
  return noh_bathe_critical_omega(std::get<NohBatheParams>(params).p);
}

const MethodSpectrum kSpectrum{3, amplification, eigenvalues, unbounded_high_frequency_radius,
                               stability_limit};

// p = ½ has no dissipation; p < 1 by its range (0.99: the scan's end inside it). ξ̄ is not
// monotone in p.
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"noh-bathe", "noh-bathe", "p", 0.5, 0.99,
     [](double p) -> MethodParams { return NohBatheParams{.p = p}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<NohBatheParams>(params);
  // Below ½ the determinant of the amplification matrix exceeds 1 at every Ω > 0.
  if (!(p.p >= 0.5 && p.p < 1.0)) {
    return ParameterError{"p", format_value(p.p),
                          "must lie in [0.5, 1) (below 0.5 the scheme is unstable for "
                          "every time step; 1 is excluded)"};
  }
  return std::nullopt;
}

// Its stepper: the Noh–Bathe scheme (core/methods/noh_bathe.hpp).
StepperCoefficients stepper(const MethodParams& params) {
  return noh_bathe_coefficients(std::get<NohBatheParams>(params));
}

}  // namespace

NohBatheCoefficients noh_bathe_coefficients(const NohBatheParams& params) {
  const double p = params.p;
  NohBatheCoefficients c{};
  c.p = p;
  c.q1 = (1.0 - 2.0 * p) / (2.0 * p * (1.0 - p));
  c.q2 = 0.5 - p * c.q1;
  c.q0 = -c.q1 - c.q2 + 0.5;
  return c;
}

double noh_bathe_critical_omega(double p) {
  if (!(p >= 0.5 && p < 1.0)) return std::numeric_limits<double>::quiet_NaN();
  double omega2 = 4.0 / ((1.0 - p) * (3.0 * p - 1.0));  // eigenvalue +1
  const double d = (1.0 - p) * (1.0 - p) * (2.0 * p - 1.0);
  if (d > 0.0) omega2 = std::min(omega2, std::sqrt(8.0 / d));  // det = −1
  const double c = (1.0 - p) * (4.0 * p * p - 3.0 * p + 1.0);
  if (c < 0.25) omega2 = std::min(omega2, 8.0 / (1.0 + std::sqrt(1.0 - 4.0 * c)));  // −1
  return std::sqrt(omega2);
}

MethodDescriptor noh_bathe_method() {
  return {
      .kind = MethodKind::noh_bathe,
      .name = "noh-bathe",
      .summary =
          "Noh-Bathe explicit (Noh & Bathe 2013, doi:10.1016/j.compstruc.2013.06.007): two "
          "explicit sub-steps, to t + p*dt and t + dt; second order, dissipative for p > "
          "1/2, stable up to omega*dt = Omega_crit(p) (3.745 at p = 0.54); contact enforced "
          "at both sub-steps",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .stages = 2,
      .spectrum = &kSpectrum,
      .same_parameters = same,
      .damping_families = kDampingFamilies,
      .defaults = default_of<NohBatheParams>,
      .validate = check,
      .stepper = stepper,
      .stable_step = "Omega_crit(p) over the bound on omega_max",
  };
}

}  // namespace impactid
