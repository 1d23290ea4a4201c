// The KR-α explicit method (core/methods/kr_alpha.hpp): its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"rho_inf"};

MadeMethod make(const MethodArguments& given) {
  KrAlphaParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  return p;
}

// ρ∞, then the scalars the matrices α1, α2, α3 are built from (derived).
MethodValues values(const MethodParams& params) {
  const auto& p = std::get<KrAlphaParams>(params);
  const KrAlphaCoefficients c = kr_alpha_coefficients(p);
  return {{"rho_inf", p.rho_inf, false},
          {"alpha_m", c.alpha_m, true},
          {"alpha_f", c.alpha_f, true},
          {"beta", c.beta, true},
          {"gamma", c.gamma, true}};
}

bool same(const MethodParams& a, const MethodParams& b) {
  return std::get<KrAlphaParams>(a).rho_inf == std::get<KrAlphaParams>(b).rho_inf;
}

// The KR-α explicit step (core/methods/kr_alpha.hpp without damping and contact) on the reported
// state x = (u, Δt·v, Δt²·a): with D = 1 + βΩ², α1 = 1/D, N = α_m + α_f·βΩ², E = D − N (D·α3 = N,
// D·(1 − α3) = E) and the method's own velocity V̂ = V − γ·α1·A,
//   u₁ = u + V̂ + (½ + γ)·α1·A,   V̂₁ = V̂ + α1·A,
//   A₁ = −(N·A + D·Ω²·((1−α_f)·u₁ + α_f·u))/E   (from (1 − α3)·A₁ + α3·A + Ω²·u_{1−α_f} = 0),
//   V₁ = V̂₁ + γ·α1·A₁:
// similar to the matrix on (u, V̂, A), so the same eigenvalues.
// Explicit, so A₁ grows like Ω²: eigenvalues() rescales it (the third component by Ω²) past Ω = 1.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> kr_alpha_amplification(const KrAlphaCoefficients& c, double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar omega = omega_dt, w2 = omega * omega, one = 1;
  const Scalar beta = c.beta, alpha_m = c.alpha_m, alpha_f = c.alpha_f;
  const Scalar d = one + beta * w2, n = alpha_m + alpha_f * beta * w2;
  const Scalar e = (one - alpha_m) + (one - alpha_f) * beta * w2;
  const Scalar alpha1 = one / d, half = one / 2, gamma = c.gamma;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row v_hat = e_v - (gamma * alpha1) * e_a;
  const Row u1 = e_u + v_hat + ((half + gamma) * alpha1) * e_a;
  const Row a1 = -((n / e) * e_a + (d * w2 / e) * ((one - alpha_f) * u1 + alpha_f * e_u));
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u1;
  a.row(1) = v_hat + alpha1 * e_a + (gamma * alpha1) * a1;
  a.row(2) = a1;
  return a;
}

Eigen::MatrixXd amplification(const MethodParams& params, double omega_dt) {
  return kr_alpha_amplification<double>(kr_alpha_coefficients(std::get<KrAlphaParams>(params)),
                                        omega_dt);
}

// Explicit: its Δt²·a₁ grows like Ω², rescaled past Ω = 1.
std::vector<SpectralEigenvalue> eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(kr_alpha_amplification<SpectralScalar>(
                                  kr_alpha_coefficients(std::get<KrAlphaParams>(params)), omega_dt),
                              omega_dt, /*explicit_acceleration=*/true);
}

// The limit of kr_alpha_amplification as Ω → ∞ on (u, Δt·v, Δt²·a/Ω²), in closed form
// (α1·Ω² → 1/β, D/E → 1/(1−α_f), N/E → α_f/(1−α_f) = ρ∞). At ρ∞ = 0 its eigenvalues are a
// triple root 0, accurate only to about ε^(1/3) ≈ 5e-7 in long double.
double high_frequency_radius(const MethodParams& params) {
  using Extended = SpectralScalar;
  const auto& kr_alpha = std::get<KrAlphaParams>(params);
  const KrAlphaCoefficients c = kr_alpha_coefficients(kr_alpha);
  const Extended q = Extended(0.5) + c.gamma, beta = c.beta, r = kr_alpha.rho_inf;
  SpectralMatrix b(3, 3);
  // clang-format off
  b << 1,      1,  q / beta,
       0,      1,  1 / beta,
       -1 - r, -1, -q / beta - r;
  // clang-format on
  std::vector<SpectralEigenvalue> lambda;
  append_eigenvalues(std::move(b), lambda);
  return static_cast<double>(largest_modulus(lambda));
}

const MethodSpectrum kSpectrum{3, amplification, eigenvalues, high_frequency_radius,
                               no_stability_limit};

constexpr MethodDampingFamily kDampingFamilies[] = {
    {"kr-alpha", "kr-alpha", "rho_inf", 1.0, 0.0,
     [](double rho_inf) -> MethodParams { return KrAlphaParams{.rho_inf = rho_inf}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<KrAlphaParams>(params);
  return require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]");
}

// Its stepper: KR-α's (core/methods/kr_alpha.hpp).
StepperCoefficients stepper(const MethodParams& params) {
  return kr_alpha_coefficients(std::get<KrAlphaParams>(params));
}

}  // namespace

KrAlphaCoefficients kr_alpha_coefficients(const KrAlphaParams& params) {
  const auto g = generalized_alpha_from_rho_inf(params.rho_inf);
  return {g.alpha_m, g.alpha_f, g.bg.beta, g.bg.gamma};
}

MethodDescriptor kr_alpha_method() {
  return {
      .kind = MethodKind::kr_alpha,
      .name = "kr-alpha",
      .summary =
          "KR-alpha explicit (Kolay & Ricles 2014, doi:10.1002/eqe.2401): explicit "
          "displacement and velocity through the model-based matrices alpha1, alpha2, "
          "alpha3, generalized-alpha's equilibrium; second order, unconditionally stable "
          "(linear systems), high-frequency spectral radius rho_inf; contact enforced as a "
          "forward increment",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .spectrum = &kSpectrum,
      .same_parameters = same,
      .damping_families = kDampingFamilies,
      .defaults = default_of<KrAlphaParams>,
      .validate = check,
      .stepper = stepper,
  };
}

}  // namespace impactid
