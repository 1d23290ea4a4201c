// The ρ∞-Bathe composite scheme (core/methods/bathe_composite.hpp), a member of the composite
// family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"rho_inf", "substep_ratio"};

MadeMethod make(const MethodArguments& given) {
  RhoBatheParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  p.gamma = given.number("substep_ratio");
  return p;
}

MethodValues values(const MethodParams& params) {
  const auto& p = std::get<RhoBatheParams>(params);
  MethodValues out{{"rho_inf", p.rho_inf, false},
                   {"substep_ratio", composite_coefficients(params).gamma, false}};
  add_composite_weights(params, out);
  return out;
}

// At its default sub-step ratio γ₀(ρ∞).
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"rho-bathe", "rho-bathe", "rho_inf", 1.0, 0.0,
     [](double rho_inf) -> MethodParams { return RhoBatheParams{.rho_inf = rho_inf}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<RhoBatheParams>(params);
  if (auto e = require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]")) {
    return e;
  }
  if (p.gamma && !(*p.gamma > 0.0 && *p.gamma < 1.0)) {
    return ParameterError{"substep_ratio", format_value(*p.gamma),
                          "must lie in (0, 1), both ends excluded"};
  }
  return std::nullopt;
}

CompositeCoefficients composite(const MethodParams& params) {
  const auto& p = std::get<RhoBatheParams>(params);
  return composite_step_coefficients(p.rho_inf,
                                     p.gamma.value_or(rho_bathe_default_gamma(p.rho_inf)));
}

}  // namespace

MethodDescriptor rho_bathe_method() {
  return {
      .kind = MethodKind::rho_bathe,
      .name = "rho-bathe",
      .summary =
          "rho_inf-Bathe composite (Noh & Bathe 2019, doi:10.1016/j.compstruc.2018.11.001): "
          "a trapezoidal sub-step to t + gamma*dt, then a 3-point formula; implicit, second "
          "order, high-frequency spectral radius rho_inf; contact enforced at both "
          "sub-steps",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .stages = 2,
      .spectrum = &kCompositeSpectrum,
      .same_parameters = same_composite_coefficients,
      .damping_families = kDampingFamilies,
      .defaults = default_of<RhoBatheParams>,
      .validate = check,
      .composite_coefficients = composite,
      .massless_dofs = kCompositeMasslessDofs,
  };
}

}  // namespace impactid
