// Houbolt's method (core/methods/houbolt.hpp): its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

// Houbolt's recurrence (2 + Ω²)·u_{n+1} = 5u_n − 4u_{n−1} + u_{n−2} (core/methods/houbolt.hpp
// without damping and contact) as the companion matrix on y_n = (u_n, u_{n−1}, u_{n−2}).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> houbolt_companion(double omega_dt) {
  const Scalar omega = omega_dt, d = 2 + omega * omega;
  Eigen::Matrix<Scalar, 3, 3> a;
  // clang-format off
  a << 5 / d, -4 / d, 1 / d,
       1,     0,      0,
       0,     1,      0;
  // clang-format on
  return a;
}

Eigen::MatrixXd amplification(const MethodParams&, double omega_dt) {
  return houbolt_companion<double>(omega_dt);
}

// On the backward differences (u_n, ∇u_n/σ, ∇²u_n/σ²), σ = min(Ω, 1).
std::vector<SpectralEigenvalue> eigenvalues(const MethodParams&, double omega_dt) {
  using Extended = SpectralScalar;
  std::vector<SpectralEigenvalue> lambda;
  const Extended omega = omega_dt;
  const Extended sigma = std::min<Extended>(omega, 1), w2 = omega * omega, d = 2 + w2;
  if (sigma == 0) return {1, 1, 0.5L};
  SpectralMatrix b(3, 3);
  // clang-format off
  b << 2,              2 * sigma,   sigma * sigma,
       -w2 / sigma,    2,           sigma,
       -w2 / (sigma * sigma), -w2 / sigma, 1;
  // clang-format on
  b /= d;
  append_eigenvalues(std::move(b), lambda);
  return lambda;
}

// Past Ω = 1 the backward-difference form of eigenvalues() tends to the strictly lower
// triangular [[0, 0, 0], [−1, 0, 0], [−1, −1, 0]], nilpotent: ρ∞ = 0 exactly (ρ falls like
// Ω^(−2/3): (2 + Ω²)·λ³ ≈ 1).
double high_frequency_radius(const MethodParams&) {
  return 0.0;
}

const MethodSpectrum kSpectrum{3, amplification, eigenvalues, high_frequency_radius,
                               no_stability_limit};

// Its stepper: Houbolt's (core/methods/houbolt.hpp), whose coefficients are fixed.
StepperCoefficients stepper(const MethodParams&) {
  return houbolt_coefficients();
}

}  // namespace

HouboltCoefficients houbolt_coefficients() {
  HouboltCoefficients c{};
  c.first = kLinearAcceleration;
  c.second = {0.0, 2.0 / 5.0, 0.0, 4.0 / 5.0, 0.0, 0.0, 1.0};
  c.steady = {0.0, 0.5, 0.0, 11.0 / 12.0, 0.0, 0.0, 1.0};
  return c;
}

MethodDescriptor houbolt_method() {
  return {
      .kind = MethodKind::houbolt,
      .name = "houbolt",
      .summary =
          "Houbolt (Houbolt 1950, doi:10.2514/8.1722): backward differences of the cubic "
          "through four displacements; implicit, three-step, second order, rho_inf = 0, "
          "dissipative at every frequency; started by the same cubic on the initial "
          "velocity and acceleration",
      .parameters = {},
      .make = make_default<HouboltParams>,
      .values = no_values,
      .choices = no_choices,
      .spectrum = &kSpectrum,
      .same_parameters = always_same,
      .defaults = default_of<HouboltParams>,
      .validate = no_check,
      .stepper = stepper,
      .massless_dofs = kHouboltMasslessDofs,
  };
}

}  // namespace impactid
