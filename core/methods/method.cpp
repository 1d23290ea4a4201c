#include "core/methods/method.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace impactid {
namespace {

constexpr double kMax = std::numeric_limits<double>::max();

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
// C++20 deduces this guide for aggregates (P1816R0); clang 14, which builds the sanitizer and
// fuzzer targets (scripts/sanitize), does not yet, so it is spelled out.
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

const char* to_string(CdmVelocity kind) {
  return kind == CdmVelocity::central ? "central" : "backward";
}
std::optional<CdmVelocity> cdm_velocity_from_string(const std::string& name) {
  if (name == "central") return CdmVelocity::central;
  if (name == "backward") return CdmVelocity::backward;
  return std::nullopt;
}

const char* to_string(ContactWeighting kind) {
  return kind == ContactWeighting::endpoint ? "endpoint" : "weighted";
}
std::optional<ContactWeighting> contact_weighting_from_string(const std::string& name) {
  if (name == "endpoint") return ContactWeighting::endpoint;
  if (name == "weighted") return ContactWeighting::weighted;
  return std::nullopt;
}

MethodKind kind_of(const MethodParams& params) {
  return std::visit(
      Overloaded{
          [](const CentralDifferenceParams&) { return MethodKind::central_difference; },
          [](const BackwardEulerParams&) { return MethodKind::backward_euler; },
          [](const NewmarkParams&) { return MethodKind::newmark; },
          [](const HhtParams&) { return MethodKind::hht; },
          [](const GeneralizedAlphaParams&) { return MethodKind::generalized_alpha; },
          [](const BatheParams&) { return MethodKind::bathe; },
          [](const RhoBatheParams&) { return MethodKind::rho_bathe; },
          [](const TrBdf2Params&) { return MethodKind::tr_bdf2; },
          [](const HouboltParams&) { return MethodKind::houbolt; },
          [](const WilsonThetaParams&) { return MethodKind::wilson_theta; },
          [](const NohBatheParams&) { return MethodKind::noh_bathe; },
          [](const KimExplicitParams&) { return MethodKind::kim_explicit; },
          [](const KrAlphaParams&) { return MethodKind::kr_alpha; },
      },
      params);
}

MethodParams default_params(MethodKind kind) {
  switch (kind) {
    case MethodKind::central_difference:
      return CentralDifferenceParams{};
    case MethodKind::backward_euler:
      return BackwardEulerParams{};
    case MethodKind::newmark:
      return NewmarkParams{};
    case MethodKind::hht:
      return HhtParams{};
    case MethodKind::generalized_alpha:
      return GeneralizedAlphaParams{};
    case MethodKind::bathe:
      return BatheParams{};
    case MethodKind::rho_bathe:
      return RhoBatheParams{};
    case MethodKind::tr_bdf2:
      return TrBdf2Params{};
    case MethodKind::houbolt:
      return HouboltParams{};
    case MethodKind::wilson_theta:
      return WilsonThetaParams{};
    case MethodKind::noh_bathe:
      return NohBatheParams{};
    case MethodKind::kim_explicit:
      return KimExplicitParams{};
    case MethodKind::kr_alpha:
      return KrAlphaParams{};
  }
  return CentralDifferenceParams{};
}

std::optional<ParameterError> validate(const MethodParams& params) {
  return std::visit(
      Overloaded{
          [](const CentralDifferenceParams&) -> std::optional<ParameterError> { return {}; },
          [](const BackwardEulerParams&) -> std::optional<ParameterError> { return {}; },
          [](const NewmarkParams& p) -> std::optional<ParameterError> {
            if (p.coefficients) {
              if (auto e = require_in_range("beta", p.coefficients->beta,
                                            std::numeric_limits<double>::min(), kMax,
                                            "must be positive and finite")) {
                return e;
              }
              return require_in_range("gamma", p.coefficients->gamma, 0.0, kMax,
                                      "must be >= 0 and finite");
            }
            return require_in_range("delta", p.delta, 0.0, kMax,
                                    "must be >= 0 and finite (eq. 13)");
          },
          [](const HhtParams& p) -> std::optional<ParameterError> {
            if (auto e = require_in_range("alpha", p.alpha, -0.5, 0.0, "must lie in [-0.5, 0]")) {
              return e;
            }
            if (p.delta) {
              return require_in_range("delta", *p.delta, 0.0, kMax,
                                      "must be >= 0 and finite (eq. 13)");
            }
            return std::nullopt;
          },
          [](const GeneralizedAlphaParams& p) -> std::optional<ParameterError> {
            return require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]");
          },
          [](const BatheParams&) -> std::optional<ParameterError> { return {}; },
          [](const TrBdf2Params&) -> std::optional<ParameterError> { return {}; },
          [](const RhoBatheParams& p) -> std::optional<ParameterError> {
            if (auto e = require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]")) {
              return e;
            }
            if (p.gamma && !(*p.gamma > 0.0 && *p.gamma < 1.0)) {
              return ParameterError{"substep_ratio", format_value(*p.gamma),
                                    "must lie in (0, 1), both ends excluded"};
            }
            return std::nullopt;
          },
          [](const HouboltParams&) -> std::optional<ParameterError> { return {}; },
          [](const WilsonThetaParams& p) -> std::optional<ParameterError> {
            return require_in_range(
                "theta", p.theta, kWilsonThetaMinimum, kMax,
                "must be >= (1+sqrt(3))/2 = 1.3660254 (unconditional stability) and finite");
          },
          [](const NohBatheParams& p) -> std::optional<ParameterError> {
            // Below ½ the determinant of the amplification matrix exceeds 1 at every Ω > 0.
            if (!(p.p >= 0.5 && p.p < 1.0)) {
              return ParameterError{"p", format_value(p.p),
                                    "must lie in [0.5, 1) (below 0.5 the scheme is unstable for "
                                    "every time step; 1 is excluded)"};
            }
            return std::nullopt;
          },
          [](const KimExplicitParams& p) -> std::optional<ParameterError> {
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
          },
          [](const KrAlphaParams& p) -> std::optional<ParameterError> {
            return require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]");
          },
      },
      params);
}

BetaGamma newmark_from_delta(double delta) {
  return {0.25 * (1.0 + delta) * (1.0 + delta), 0.5 + delta};
}

namespace {

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

struct GeneralizedAlphaCoefficients {
  double alpha_m, alpha_f;
  BetaGamma bg;
};

// Chung & Hulbert 1993, eqs 25 and 17.
GeneralizedAlphaCoefficients generalized_alpha_from_rho_inf(double rho_inf) {
  const double alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
  const double alpha_f = rho_inf / (rho_inf + 1.0);
  const double gamma = 0.5 - alpha_m + alpha_f;
  const double beta = 0.25 * (1.0 - alpha_m + alpha_f) * (1.0 - alpha_m + alpha_f);
  return {alpha_m, alpha_f, {beta, gamma}};
}

double hht_delta(const HhtParams& p) {
  return p.delta ? *p.delta : -p.alpha;
}

}  // namespace

ImplicitCoefficients implicit_coefficients(const MethodParams& params) {
  return std::visit(
      Overloaded{
          // Not implicit: callers dispatch central difference elsewhere. The values would be
          // Newmark β = 0, γ = ½, which the acceleration-form kernel cannot use as they stand.
          [](const CentralDifferenceParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 1.0};
          },
          [](const BackwardEulerParams&) {
            return ImplicitCoefficients{0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0};
          },
          [](const NewmarkParams& p) {
            return newmark_family(p.coefficients ? *p.coefficients : newmark_from_delta(p.delta),
                                  0.0, 0.0, ContactWeighting::endpoint);
          },
          [](const HhtParams& p) {
            return newmark_family(newmark_from_delta(hht_delta(p)), 0.0, -p.alpha, p.contact);
          },
          [](const GeneralizedAlphaParams& p) {
            const auto g = generalized_alpha_from_rho_inf(p.rho_inf);
            return newmark_family(g.bg, g.alpha_m, g.alpha_f, p.contact);
          },
          // Not single-step: callers step the composite schemes by composite_coefficients().
          [](const BatheParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          [](const TrBdf2Params&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          [](const RhoBatheParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          // Not single-step: stepped by houbolt_coefficients(), wilson_theta_coefficients().
          [](const HouboltParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          [](const WilsonThetaParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          // Explicit: stepped by noh_bathe_coefficients() (core/methods/noh_bathe.hpp).
          [](const NohBatheParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          // Explicit: stepped by kim_explicit_coefficients() (core/methods/kim_explicit.hpp).
          [](const KimExplicitParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
          // Explicit and model-based: stepped by kr_alpha_coefficients()
          // (core/methods/kr_alpha.hpp).
          [](const KrAlphaParams&) {
            return ImplicitCoefficients{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
          },
      },
      params);
}

bool is_single_step_implicit(const MethodParams& params) {
  switch (kind_of(params)) {
    case MethodKind::backward_euler:
    case MethodKind::newmark:
    case MethodKind::hht:
    case MethodKind::generalized_alpha:
      return true;
    default:
      return false;
  }
}

double rho_bathe_default_gamma(double rho_inf) {
  if (rho_inf >= 1.0) return 0.5;
  return (2.0 - std::sqrt(2.0 + 2.0 * rho_inf)) / (1.0 - rho_inf);
}

CompositeCoefficients composite_coefficients(const MethodParams& params) {
  double rho_inf = 0.0, gamma = 0.5;  // the original Bathe scheme
  if (const auto* p = std::get_if<RhoBatheParams>(&params)) {
    rho_inf = p->rho_inf;
    gamma = p->gamma.value_or(rho_bathe_default_gamma(p->rho_inf));
  } else if (std::holds_alternative<TrBdf2Params>(params)) {
    gamma = rho_bathe_default_gamma(0.0);  // 2 − √2
  }
  CompositeCoefficients c{};
  c.gamma = gamma;
  c.q1 = (rho_inf + 1.0) / (2.0 * gamma * (rho_inf - 1.0) + 4.0);
  c.q2 = 0.5 - gamma * c.q1;
  c.q0 = 1.0 - c.q1 - c.q2;
  c.first = {0.25, 0.25, 0.5, 0.5, 0.0, 0.0, 1.0};  // trapezoidal: β = 1/4, γ = 1/2
  c.second = {0.0, c.q2 * c.q2, 0.0, c.q2, 0.0, 0.0, 1.0};
  return c;
}

bool is_composite(const MethodParams& params) {
  switch (kind_of(params)) {
    case MethodKind::bathe:
    case MethodKind::rho_bathe:
    case MethodKind::tr_bdf2:
      return true;
    default:
      return false;
  }
}

namespace {
// The linear-acceleration member (Newmark β = 1/6, γ = ½): Houbolt's first step, Wilson-θ's
// extended step.
constexpr ImplicitCoefficients kLinearAcceleration{1.0 / 3.0, 1.0 / 6.0, 0.5, 0.5, 0.0, 0.0, 1.0};
}  // namespace

HouboltCoefficients houbolt_coefficients() {
  HouboltCoefficients c{};
  c.first = kLinearAcceleration;
  c.second = {0.0, 2.0 / 5.0, 0.0, 4.0 / 5.0, 0.0, 0.0, 1.0};
  c.steady = {0.0, 0.5, 0.0, 11.0 / 12.0, 0.0, 0.0, 1.0};
  return c;
}

WilsonThetaCoefficients wilson_theta_coefficients(const WilsonThetaParams& params) {
  return {params.theta, kLinearAcceleration};
}

NohBatheCoefficients noh_bathe_coefficients(const NohBatheParams& params) {
  const double p = params.p;
  NohBatheCoefficients c{};
  c.p = p;
  c.q1 = (1.0 - 2.0 * p) / (2.0 * p * (1.0 - p));
  c.q2 = 0.5 - p * c.q1;
  c.q0 = -c.q1 - c.q2 + 0.5;
  return c;
}

KrAlphaCoefficients kr_alpha_coefficients(const KrAlphaParams& params) {
  const auto g = generalized_alpha_from_rho_inf(params.rho_inf);
  return {g.alpha_m, g.alpha_f, g.bg.beta, g.bg.gamma};
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

std::optional<BetaGamma> reported_beta_gamma(const MethodParams& params) {
  switch (kind_of(params)) {
    case MethodKind::central_difference:
    case MethodKind::backward_euler:
    case MethodKind::bathe:
    case MethodKind::rho_bathe:
    case MethodKind::tr_bdf2:
    case MethodKind::houbolt:
    case MethodKind::wilson_theta:
    case MethodKind::noh_bathe:
    case MethodKind::kim_explicit:
    case MethodKind::kr_alpha:
      return std::nullopt;
    default: {
      const ImplicitCoefficients c = implicit_coefficients(params);
      return BetaGamma{c.b1, c.g1};
    }
  }
}

}  // namespace impactid
