// Central difference (core/methods/central_difference.hpp): its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"cdm_velocity"};

MadeMethod make(const MethodArguments& given) {
  CentralDifferenceParams p;
  if (const auto word = given.choice("cdm_velocity")) {
    const auto velocity = cdm_velocity_from_string(*word);
    if (!velocity) return bad_choice("cdm_velocity", *word);
    p.velocity = *velocity;
  }
  return p;
}

MethodChoices choices(const MethodParams& params) {
  return {{"cdm_velocity", to_string(std::get<CentralDifferenceParams>(params).velocity)}};
}

bool same(const MethodParams& a, const MethodParams& b) {
  return std::get<CentralDifferenceParams>(a).velocity ==
         std::get<CentralDifferenceParams>(b).velocity;
}

// The two-step recurrence u_{n+1} = (2 − Ω²)·u_n − u_{n−1} on y_n = (u_n, u_{n−1}) (the velocity
// variant does not matter without damping).
Eigen::MatrixXd amplification(const MethodParams&, double omega_dt) {
  Eigen::Matrix2d a;
  a << 2.0 - omega_dt * omega_dt, -1.0, 1.0, 0.0;
  return a;
}

// On the state (u_n, (u_n − u_{n−1})/σ), σ = min(Ω, 1), in which
// B = [[1 − Ω², σ], [−Ω²/σ, 1]] (the leapfrog form), not a diagonal similarity.
std::vector<SpectralEigenvalue> eigenvalues(const MethodParams&, double omega_dt) {
  using Extended = SpectralScalar;
  std::vector<SpectralEigenvalue> lambda;
  const Extended omega = omega_dt;
  const Extended sigma = std::min<Extended>(omega, 1);
  if (sigma == 0) return {1, 1};
  SpectralMatrix b(2, 2);
  b << 1 - omega * omega, sigma, -omega * omega / sigma, 1;
  append_eigenvalues(std::move(b), lambda);
  return lambda;
}

// Explicit: stable up to Ω = 2 (lumped mass, no damping).
double stability_limit(const MethodParams&) {
  return 2.0;
}

const MethodSpectrum kSpectrum{2, amplification, eigenvalues, unbounded_high_frequency_radius,
                               stability_limit};

// Its stepper: central difference (core/methods/central_difference.hpp).
StepperCoefficients stepper(const MethodParams& params) {
  return CentralDifferenceCoefficients{std::get<CentralDifferenceParams>(params).velocity};
}

}  // namespace

MethodDescriptor cdm_method() {
  return {
      .kind = MethodKind::central_difference,
      .name = "cdm",
      .summary =
          "central difference with Carpenter's forward-increment multiplier (eqs 1-7; "
          "Carpenter, Taylor & Katona 1991, doi:10.1002/nme.1620320107): explicit, second "
          "order, no numerical dissipation, stable below Courant 1 with a lumped mass",
      .parameters = kParameters,
      .make = make,
      .values = no_values,
      .choices = choices,
      .spectrum = &kSpectrum,
      .same_parameters = same,
      .defaults = default_of<CentralDifferenceParams>,
      .validate = no_check,
      .stepper = stepper,
      .massless_dofs =
          "solved from its static equation K_c*u + lambda = 0 at t + dt within the step, with "
          "the contact (its force reported with the next sample); not with rayleigh_stiffness > 0",
      .massless_dofs_undamped = true,
      .two_step_displacement = true,
  };
}

}  // namespace impactid
