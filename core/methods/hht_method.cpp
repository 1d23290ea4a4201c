// HHT-α (eq. 14), a member of the single-step implicit family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"delta", "alpha", "hht_contact"};

MadeMethod make(const MethodArguments& given) {
  HhtParams p;
  if (const auto alpha = given.number("alpha")) p.alpha = *alpha;
  p.delta = given.number("delta");
  if (auto e = read_contact(given, p.contact)) return *e;
  return p;
}

MethodValues values(const MethodParams& params) {
  const auto& p = std::get<HhtParams>(params);
  MethodValues out{{"delta", p.delta.value_or(-p.alpha), false}, {"alpha", p.alpha, false}};
  add_beta_gamma(params, true, out);
  return out;
}

MethodChoices choices(const MethodParams& params) {
  return {{"hht_contact", to_string(std::get<HhtParams>(params).contact)}};
}

// Two families over α ∈ [−0.5, 0]: along the paper's eq. 19 (δ = −1.5α) and with δ = −α (eq. 15,
// second order; δ unset).
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"hht-eq19", "hht (delta = -1.5*alpha)", "alpha", 0.0, -0.5,
     [](double alpha) -> MethodParams { return HhtParams{.alpha = alpha, .delta = -1.5 * alpha}; },
     [](double alpha) -> std::vector<std::pair<const char*, double>> {
       return {{"alpha", alpha}, {"delta", -1.5 * alpha}};
     }},
    {"hht-eq15", "hht (delta = -alpha)", "alpha", 0.0, -0.5,
     [](double alpha) -> MethodParams { return HhtParams{.alpha = alpha}; },
     [](double alpha) -> std::vector<std::pair<const char*, double>> {
       return {{"alpha", alpha}, {"delta", -alpha}};
     }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<HhtParams>(params);
  if (auto e = require_in_range("alpha", p.alpha, -0.5, 0.0, "must lie in [-0.5, 0]")) {
    return e;
  }
  if (p.delta) {
    return require_in_range("delta", *p.delta, 0.0, kFiniteMax, "must be >= 0 and finite (eq. 13)");
  }
  return std::nullopt;
}

double hht_delta(const HhtParams& p) {
  return p.delta ? *p.delta : -p.alpha;
}

ImplicitCoefficients implicit(const MethodParams& params) {
  const auto& p = std::get<HhtParams>(params);
  return newmark_family(newmark_from_delta(hht_delta(p)), 0.0, -p.alpha, p.contact);
}

}  // namespace

MethodDescriptor hht_method() {
  return {
      .kind = MethodKind::hht,
      .name = "hht",
      .summary =
          "HHT-alpha (eq. 14; Hilber, Hughes & Taylor 1977, doi:10.1002/eqe.4290050306): "
          "implicit, second order at delta = -alpha, high-frequency spectral radius "
          "(1+alpha)/(1-alpha) for alpha in [-1/3, 0]",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .damping_families = kDampingFamilies,
      .defaults = default_of<HhtParams>,
      .validate = check,
      .implicit_coefficients = implicit,
      .reports_beta_gamma = true,
      .massless_dofs = kImplicitMasslessDofs,
  };
}

}  // namespace impactid
