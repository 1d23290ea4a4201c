// Wilson-θ (core/methods/wilson_theta.hpp): its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"theta"};

MadeMethod make(const MethodArguments& given) {
  WilsonThetaParams p;
  if (const auto theta = given.number("theta")) p.theta = *theta;
  return p;
}

MethodValues values(const MethodParams& params) {
  return {{"theta", std::get<WilsonThetaParams>(params).theta, false}};
}

bool same(const MethodParams& a, const MethodParams& b) {
  return std::get<WilsonThetaParams>(a).theta == std::get<WilsonThetaParams>(b).theta;
}

// Wilson-θ's step (core/methods/wilson_theta.hpp) on x = (u, Δt·v, Δt²·a): equilibrium at t + θΔt,
//   A_θ = −s·(u + θ·V + θ²/3·A)/(t + s·θ²/6)   ((s, t) as in implicit_amplification),
// then A₁ = (1 − 1/θ)·A + A_θ/θ, V₁ = V + (A + A₁)/2, u₁ = u + V + (2A + A₁)/6.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> wilson_theta_amplification(double theta_value, double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar theta = theta_value, omega = omega_dt, one = 1;
  const Scalar s = omega_dt > 1.0 ? one : omega * omega;
  const Scalar t = omega_dt > 1.0 ? one / (omega * omega) : one;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row a_theta = Row(1, theta, theta * theta / 3) * (-s / (t + s * theta * theta / 6));
  const Row a1 = (one - one / theta) * e_a + a_theta / theta;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = e_u + e_v + e_a / 3 + a1 / 6;
  a.row(1) = e_v + e_a / 2 + a1 / 2;
  a.row(2) = a1;
  return a;
}

Eigen::MatrixXd amplification(const MethodParams& params, double omega_dt) {
  return wilson_theta_amplification<double>(std::get<WilsonThetaParams>(params).theta, omega_dt);
}

std::vector<SpectralEigenvalue> eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(wilson_theta_amplification<SpectralScalar>(
                                  std::get<WilsonThetaParams>(params).theta, omega_dt),
                              omega_dt);
}

// The limit of wilson_theta_amplification as Ω → ∞ (s = 1, t = 0), in closed form; its
// eigenvalues are distinct for θ >= (1 + √3)/2, so accurate to rounding.
double high_frequency_radius(const MethodParams& params) {
  using Extended = SpectralScalar;
  const Extended theta = std::get<WilsonThetaParams>(params).theta, t2 = theta * theta,
                 t3 = t2 * theta;
  SpectralMatrix b(3, 3);
  // clang-format off
  b << 1 - 1 / t3,  1 - 1 / t2,  (theta - 1) / (2 * theta),
       -3 / t3,     1 - 3 / t2,  (theta - Extended(1.5)) / theta,
       -6 / t3,     -6 / t2,     (theta - 3) / theta;
  // clang-format on
  std::vector<SpectralEigenvalue> lambda;
  append_eigenvalues(std::move(b), lambda);
  return static_cast<double>(largest_modulus(lambda));
}

const MethodSpectrum kSpectrum{3, amplification, eigenvalues, high_frequency_radius,
                               no_stability_limit};

// θ from its stability bound (1 + √3)/2 (ξ̄(1) = 0.034 there) to 4, which reaches ξ̄(1) = 0.2
// and more, beyond any damping a user would match.
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"wilson-theta", "wilson-theta", "theta", 1.3660254037844386, 4.0,
     [](double theta) -> MethodParams { return WilsonThetaParams{.theta = theta}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<WilsonThetaParams>(params);
  return require_in_range(
      "theta", p.theta, kWilsonThetaMinimum, kFiniteMax,
      "must be >= (1+sqrt(3))/2 = 1.3660254 (unconditional stability) and finite");
}

// Its stepper: Wilson-θ's extended step (core/methods/wilson_theta.hpp).
StepperCoefficients stepper(const MethodParams& params) {
  return wilson_theta_coefficients(std::get<WilsonThetaParams>(params));
}

}  // namespace

WilsonThetaCoefficients wilson_theta_coefficients(const WilsonThetaParams& params) {
  return {params.theta, kLinearAcceleration};
}

MethodDescriptor wilson_theta_method() {
  return {
      .kind = MethodKind::wilson_theta,
      .name = "wilson-theta",
      .summary =
          "Wilson-theta (Wilson, Farhoomand & Bathe 1972, doi:10.1002/eqe.4290010305): "
          "linear acceleration extended to t + theta*dt, equilibrium there; implicit, "
          "second order, unconditionally stable for theta >= 1.366, rho_inf 0.78 at theta "
          "= 1.4; contact enforced at t + dt",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .spectrum = &kSpectrum,
      .same_parameters = same,
      .damping_families = kDampingFamilies,
      .defaults = default_of<WilsonThetaParams>,
      .validate = check,
      .stepper = stepper,
  };
}

}  // namespace impactid
