// Generalized-α (Chung & Hulbert 1993), a member of the single-step implicit family: its
// descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"rho_inf", "hht_contact"};

MadeMethod make(const MethodArguments& given) {
  GeneralizedAlphaParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  if (auto e = read_contact(given, p.contact)) return *e;
  return p;
}

MethodValues values(const MethodParams& params) {
  MethodValues out{{"rho_inf", std::get<GeneralizedAlphaParams>(params).rho_inf, false}};
  add_beta_gamma(params, true, out);
  // Derived from ρ∞ (Chung & Hulbert 1993), as β and γ are.
  const ImplicitCoefficients c = implicit_coefficients(params);
  out.push_back({"alpha_m", c.alpha_m, true});
  out.push_back({"alpha_f", c.alpha_f, true});
  return out;
}

MethodChoices choices(const MethodParams& params) {
  return {{"hht_contact", to_string(std::get<GeneralizedAlphaParams>(params).contact)}};
}

constexpr MethodDampingFamily kDampingFamilies[] = {
    {"generalized-alpha", "generalized-alpha", "rho_inf", 1.0, 0.0,
     [](double rho_inf) -> MethodParams { return GeneralizedAlphaParams{.rho_inf = rho_inf}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<GeneralizedAlphaParams>(params);
  return require_in_range("rho_inf", p.rho_inf, 0.0, 1.0, "must lie in [0, 1]");
}

ImplicitCoefficients implicit(const MethodParams& params) {
  const auto& p = std::get<GeneralizedAlphaParams>(params);
  const auto g = generalized_alpha_from_rho_inf(p.rho_inf);
  return newmark_family(g.bg, g.alpha_m, g.alpha_f, p.contact);
}

}  // namespace

MethodDescriptor generalized_alpha_method() {
  return {
      .kind = MethodKind::generalized_alpha,
      .name = "generalized-alpha",
      .summary =
          "generalized-alpha (Chung & Hulbert 1993, doi:10.1115/1.2900803): implicit, second "
          "order, high-frequency spectral radius rho_inf with least low-frequency "
          "dissipation",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .damping_families = kDampingFamilies,
      .defaults = default_of<GeneralizedAlphaParams>,
      .validate = check,
      .implicit_coefficients = implicit,
      .reports_beta_gamma = true,
      .massless_dofs = kImplicitMasslessDofs,
  };
}

}  // namespace impactid
