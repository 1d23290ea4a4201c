#include "core/methods/method_families.hpp"

#include <algorithm>
#include <cmath>

namespace impactid {
namespace {

constexpr double kNaN = kSpectralNaN;
constexpr double kInf = kSpectralInf;

// A composite scheme's step (core/methods/bathe_composite.hpp) on x = (u, Δt·v, Δt²·a): the
// trapezoidal sub-step over γ·Δt is the family's matrix at γ·Ω on its own scaled state D·x, D =
// diag(1, γ, γ²), so x_γ = D⁻¹·A₁(γΩ)·D·x. The second sub-step, row by row over x:
//   V* = V + q0·A + q1·A_γ,   u* = u + q0·V + q1·V_γ + q2·V*,
//   u₁ = u*/(1 + q2²·Ω²),     A₁ = −Ω²·u₁,   V₁ = V* + q2·A₁,
// with A₁ = −u*/(1/Ω² + q2²) past Ω = 1 so that no entry grows with Ω.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> composite_amplification(const CompositeCoefficients& c,
                                                    double omega_dt) {
  using Matrix = Eigen::Matrix<Scalar, 3, 3>;
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar gamma = c.gamma, q0 = c.q0, q1 = c.q1, q2 = c.q2, omega = omega_dt;
  const Eigen::Matrix<Scalar, 3, 1> d(1, gamma, gamma * gamma);
  const Matrix first = d.cwiseInverse().asDiagonal() *
                       implicit_amplification<Scalar>(c.first, c.gamma * omega_dt) * d.asDiagonal();
  if (!first.allFinite()) return Matrix::Constant(Scalar(kNaN));
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row v_star = e_v + q0 * e_a + q1 * first.row(2);
  const Row u_star = e_u + q0 * e_v + q1 * first.row(1) + q2 * v_star;
  const Row u1 = u_star / (1 + q2 * q2 * omega * omega);
  const Row a1 =
      omega_dt > 1.0 ? Row(-u_star / (1 / (omega * omega) + q2 * q2)) : Row(-omega * omega * u1);
  Matrix a;
  a.row(0) = u1;
  a.row(1) = v_star + q2 * a1;
  a.row(2) = a1;
  return a;
}

// Largest modulus of a root of a·λ² + b·λ + c (a > 0). A complex pair has modulus √(c/a)
// exactly (product of the roots), so only the real case uses the discriminant.
double quadratic_root_modulus(double a, double b, double c) {
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant <= 0.0) return std::sqrt(std::abs(c / a));
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  return std::max(std::abs(q / a), q == 0.0 ? 0.0 : std::abs(c / q));
}

Eigen::MatrixXd implicit_matrix(const MethodParams& params, double omega_dt) {
  return implicit_amplification<double>(implicit_coefficients(params), omega_dt);
}

std::vector<SpectralEigenvalue> implicit_eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(
      implicit_amplification<SpectralScalar>(implicit_coefficients(params), omega_dt), omega_dt);
}

// Dividing the equation of motion by Ω² and letting Ω → ∞ leaves (1−α_f)·u₁ + α_f·u₀ = 0: a
// spurious root −α_f/(1−α_f) and the limit of the principal pair
// (core/spectral/amplification.hpp).
double implicit_high_frequency_radius(const MethodParams& params) {
  const ImplicitCoefficients c = implicit_coefficients(params);
  // Limit matrix singular: the update does not stay bounded as Ω → ∞.
  if (c.b1 <= 0.0 || c.alpha_f >= 1.0) return kInf;
  const double spurious = std::abs(c.alpha_f / (1.0 - c.alpha_f));
  const double principal = quadratic_root_modulus(c.b1, c.g1 + c.b0 - c.b1, c.g0 - c.b0);
  return std::max(spurious, principal);
}

Eigen::MatrixXd composite_matrix(const MethodParams& params, double omega_dt) {
  return composite_amplification<double>(composite_coefficients(params), omega_dt);
}

std::vector<SpectralEigenvalue> composite_eigenvalues(const MethodParams& params, double omega_dt) {
  return one_step_eigenvalues(
      composite_amplification<SpectralScalar>(composite_coefficients(params), omega_dt), omega_dt);
}

// ρ at Ω = 1e8, within about 1e-7 of the limit (the original Bathe scheme gives 5e-8 for its
// ρ∞ = 0: its spurious roots fall to 0 like 1/Ω).
double composite_high_frequency_radius(const MethodParams& params) {
  const std::vector<SpectralEigenvalue> lambda = composite_eigenvalues(params, 1e8);
  return lambda.empty() ? kNaN : static_cast<double>(largest_modulus(lambda));
}

}  // namespace

const MethodSpectrum kSingleStepImplicitSpectrum{
    3, implicit_matrix, implicit_eigenvalues, implicit_high_frequency_radius, no_stability_limit};

const MethodSpectrum kCompositeSpectrum{3, composite_matrix, composite_eigenvalues,
                                        composite_high_frequency_radius, no_stability_limit};

bool same_implicit_coefficients(const MethodParams& a, const MethodParams& b) {
  const ImplicitCoefficients x = implicit_coefficients(a);
  const ImplicitCoefficients y = implicit_coefficients(b);
  return x.b0 == y.b0 && x.b1 == y.b1 && x.g0 == y.g0 && x.g1 == y.g1 && x.alpha_m == y.alpha_m &&
         x.alpha_f == y.alpha_f && x.contact_weight == y.contact_weight;
}

bool same_composite_coefficients(const MethodParams& a, const MethodParams& b) {
  // Both sub-steps' coefficients follow from these.
  const CompositeCoefficients x = composite_coefficients(a);
  const CompositeCoefficients y = composite_coefficients(b);
  return x.gamma == y.gamma && x.q0 == y.q0 && x.q1 == y.q1 && x.q2 == y.q2;
}

ImplicitCoefficients newmark_family(BetaGamma bg, double alpha_m, double alpha_f,
                                    ContactWeighting contact) {
  return {0.5 - bg.beta,
          bg.beta,
          1.0 - bg.gamma,
          bg.gamma,
          alpha_m,
          alpha_f,
          contact == ContactWeighting::endpoint ? 1.0 : 1.0 - alpha_f};
}

GeneralizedAlphaCoefficients generalized_alpha_from_rho_inf(double rho_inf) {
  const double alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
  const double alpha_f = rho_inf / (rho_inf + 1.0);
  const double gamma = 0.5 - alpha_m + alpha_f;
  const double beta = 0.25 * (1.0 - alpha_m + alpha_f) * (1.0 - alpha_m + alpha_f);
  return {alpha_m, alpha_f, {beta, gamma}};
}

MethodValues no_values(const MethodParams&) {
  return {};
}

MethodChoices no_choices(const MethodParams&) {
  return {};
}

bool always_same(const MethodParams&, const MethodParams&) {
  return true;
}

ParameterError bad_choice(const char* name, const std::string& word) {
  return ParameterError{name, word,
                        std::string("must be one of ") + find_method_parameter(name)->choices};
}

std::optional<ParameterError> read_contact(const MethodArguments& given,
                                           ContactWeighting& contact) {
  const auto word = given.choice("hht_contact");
  if (!word) return std::nullopt;
  const auto value = contact_weighting_from_string(*word);
  if (!value) return bad_choice("hht_contact", *word);
  contact = *value;
  return std::nullopt;
}

void add_beta_gamma(const MethodParams& params, bool derived, MethodValues& out) {
  const BetaGamma bg = *reported_beta_gamma(params);
  out.push_back({"beta", bg.beta, derived});
  out.push_back({"gamma", bg.gamma, derived});
}

void add_composite_weights(const MethodParams& params, MethodValues& out) {
  const CompositeCoefficients c = composite_coefficients(params);
  out.push_back({"q0", c.q0, true});
  out.push_back({"q1", c.q1, true});
  out.push_back({"q2", c.q2, true});
}

}  // namespace impactid
