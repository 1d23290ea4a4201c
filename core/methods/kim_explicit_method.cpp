// Kim's two-stage explicit scheme (core/methods/kim_explicit.hpp): its descriptor.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"p"};

MadeMethod make(const MethodArguments& given) {
  KimExplicitParams p;
  if (const auto value = given.number("p")) p.p = *value;
  return p;
}

// p, then the stability limit Ω_crit(p) (derived).
MethodValues values(const MethodParams& params) {
  const auto& p = std::get<KimExplicitParams>(params);
  return {{"p", p.p, false}, {"omega_crit", kim_explicit_critical_omega(p.p), true}};
}

bool same(const MethodParams& a, const MethodParams& b) {
  return std::get<KimExplicitParams>(a).p == std::get<KimExplicitParams>(b).p;
}

// Kim's two-stage explicit step (core/methods/kim_explicit.hpp without damping and contact) on
// x = (u, Δt·v, Δt²·a), composed from its stages row by row:
//   u_p = u + p·V + p²/2·A,                  A_p = −Ω²·u_p,
//   ũ₁ = u + V + u0·A + up·A_p,   Ṽ₁ = V + v0·A + vp·A_p,   A₁ = −Ω²·ũ₁,
//   D = d0·A + dp·A_p + d1·A₁,    u₁ = ũ₁ + cu·D,   V₁ = Ṽ₁ + cv·D.
// Entries grow like Ω⁴, harmless within the explicit limit (Ω_crit <= 3.09).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> kim_explicit_amplification(const KimExplicitCoefficients& c,
                                                       double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar p = c.p, omega = omega_dt;
  const Scalar w2 = omega * omega;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row u_p = e_u + p * e_v + (p * p / 2) * e_a;
  const Row a_p = -w2 * u_p;
  const Row u_predicted = e_u + e_v + Scalar(c.u0) * e_a + Scalar(c.up) * a_p;
  const Row v_predicted = e_v + Scalar(c.v0) * e_a + Scalar(c.vp) * a_p;
  const Row a1 = -w2 * u_predicted;
  const Row d = Scalar(c.d0) * e_a + Scalar(c.dp) * a_p + Scalar(c.d1) * a1;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u_predicted + Scalar(c.cu) * d;
  a.row(1) = v_predicted + Scalar(c.cv) * d;
  a.row(2) = a1;
  return a;
}

Eigen::MatrixXd amplification(const MethodParams& params, double omega_dt) {
  return kim_explicit_amplification<double>(
      kim_explicit_coefficients(std::get<KimExplicitParams>(params)), omega_dt);
}

std::vector<SpectralEigenvalue> eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(
      kim_explicit_amplification<SpectralScalar>(
          kim_explicit_coefficients(std::get<KimExplicitParams>(params)), omega_dt),
      omega_dt);
}

double stability_limit(const MethodParams& params) {
  return kim_explicit_critical_omega(std::get<KimExplicitParams>(params).p);
}

const MethodSpectrum kSpectrum{3, amplification, eigenvalues, unbounded_high_frequency_radius,
                               stability_limit};

// p = ⅓ is the least dissipative end of its range, ½ the most.
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"kim-explicit", "kim-explicit", "p", 1.0 / 3.0, 0.5,
     [](double p) -> MethodParams { return KimExplicitParams{.p = p}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<KimExplicitParams>(params);
  // Below ⅓ the principal pair grows at small Ω; above ½ see KimExplicitParams.
  if (!(p.p >= 1.0 / 3.0 && p.p <= 0.5)) {
    return ParameterError{"p", format_value(p.p),
                          "must lie in [1/3, 1/2] (1/3 written 0.3333333333333333) for "
                          "kim-explicit (below 1/3 it is "
                          "unstable at every useful step; above 1/2 its stability limit "
                          "falls and no contact multiplier keeps the step's end on the "
                          "wall)"};
  }
  return std::nullopt;
}

// Its stepper: Kim's scheme (core/methods/kim_explicit.hpp).
StepperCoefficients stepper(const MethodParams& params) {
  return kim_explicit_coefficients(std::get<KimExplicitParams>(params));
}

}  // namespace

KimExplicitCoefficients kim_explicit_coefficients(const KimExplicitParams& params) {
  const double p = params.p;
  KimExplicitCoefficients c{};
  c.p = p;
  c.u0 = 0.5 * (1.0 - 1.0 / (3.0 * p));
  c.up = 1.0 / (6.0 * p);
  c.v0 = 1.0 - 1.0 / (2.0 * p);
  c.vp = 1.0 / (2.0 * p);
  c.d0 = 1.0 / p;
  c.dp = -1.0 / (p * (1.0 - p));
  c.d1 = 1.0 / (1.0 - p);
  c.cu = (1.0 - 2.0 * p) / 12.0;
  c.cv = (2.0 - 3.0 * p) / 6.0;
  return c;
}

double kim_explicit_critical_omega(double p) {
  if (!(p >= 1.0 / 3.0 && p <= 0.5)) return std::numeric_limits<double>::quiet_NaN();
  double omega2 = 12.0 * p / (1.0 - p);  // eigenvalue +1
  // Eigenvalue −1: the least positive root of a·X² + b·X + c (c < 0), in the cancellation-free
  // form q = −(b + sign(b)·√disc)/2, roots q/a and c/q.
  const double a = 12.0 * p * p * p - 6.0 * p * p - 3.0 * p + 1.0;
  const double b = -12.0 * (5.0 * p - 1.0) * (p - 1.0);
  const double c = 144.0 * p * (p - 1.0);
  const double disc = b * b - 4.0 * a * c;
  if (disc >= 0.0) {
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    for (const double root : {a != 0.0 ? q / a : -1.0, q != 0.0 ? c / q : -1.0}) {
      if (root > 0.0) omega2 = std::min(omega2, root);
    }
  }
  return std::sqrt(omega2);
}

MethodDescriptor kim_explicit_method() {
  return {
      .kind = MethodKind::kim_explicit,
      .name = "kim-explicit",
      .summary =
          "Kim two-stage explicit (Kim 2019, IJNME 120:1-28, doi:10.1002/nme.6098; not the "
          "rho_b scheme of Kim 2019, Eng. Struct. 195:358-372, ref. 17 of Serfozo & Pere "
          "2022): stages at t + p*dt and t + dt, then a quadratic correction of the end "
          "values; second order, period error O(Omega^4), stable up to omega*dt = "
          "Omega_crit(p) (sqrt(6) at p = 1/2); contact enforced at both stages",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .stages = 2,
      .spectrum = &kSpectrum,
      .same_parameters = same,
      .damping_families = kDampingFamilies,
      .defaults = default_of<KimExplicitParams>,
      .validate = check,
      .stepper = stepper,
      .stable_step = "Omega_crit(p) over the bound on omega_max",
  };
}

}  // namespace impactid
