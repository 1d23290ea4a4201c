// Newmark (eqs 11-13), a member of the single-step implicit family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

constexpr const char* kParameters[] = {"delta", "beta", "gamma"};

MadeMethod make(const MethodArguments& given) {
  NewmarkParams p;
  const auto delta = given.number("delta"), beta = given.number("beta"),
             gamma = given.number("gamma");
  if (beta || gamma) {
    if (delta) {
      return ParameterError{"delta", format_value(*delta),
                            "cannot be given with beta and gamma (eq. 13 derives them)"};
    }
    if (!beta) return ParameterError{"beta", "(missing)", "must be given with gamma"};
    if (!gamma) return ParameterError{"gamma", "(missing)", "must be given with beta"};
    p.coefficients = BetaGamma{*beta, *gamma};
  } else if (delta) {
    p.delta = *delta;
  }
  return p;
}

MethodValues values(const MethodParams& params) {
  const auto& p = std::get<NewmarkParams>(params);
  MethodValues out;
  if (!p.coefficients) out.push_back({"delta", p.delta, false});
  add_beta_gamma(params, !p.coefficients, out);
  return out;
}

// δ ∈ [0, 2]: δ has no upper bound; 2 reaches twice the damping of backward Euler (δ = 1 has
// exactly backward Euler's ξ̄).
constexpr MethodDampingFamily kDampingFamilies[] = {
    {"newmark", "newmark", "delta", 0.0, 2.0,
     [](double delta) -> MethodParams { return NewmarkParams{.delta = delta}; }},
};

std::optional<ParameterError> check(const MethodParams& params) {
  const auto& p = std::get<NewmarkParams>(params);
  if (p.coefficients) {
    if (auto e = require_in_range("beta", p.coefficients->beta, std::numeric_limits<double>::min(),
                                  kFiniteMax, "must be positive and finite")) {
      return e;
    }
    return require_in_range("gamma", p.coefficients->gamma, 0.0, kFiniteMax,
                            "must be >= 0 and finite");
  }
  return require_in_range("delta", p.delta, 0.0, kFiniteMax, "must be >= 0 and finite (eq. 13)");
}

ImplicitCoefficients implicit(const MethodParams& params) {
  const auto& p = std::get<NewmarkParams>(params);
  return newmark_family(p.coefficients ? *p.coefficients : newmark_from_delta(p.delta), 0.0, 0.0,
                        ContactWeighting::endpoint);
}

}  // namespace

MethodDescriptor newmark_method() {
  return {
      .kind = MethodKind::newmark,
      .name = "newmark",
      .summary =
          "Newmark (eqs 11-13; Newmark 1959, doi:10.1061/JMCEA3.0000098): implicit, second "
          "order only at delta = 0 (trapezoidal rule), dissipative for delta > 0",
      .parameters = kParameters,
      .make = make,
      .values = values,
      .choices = no_choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .damping_families = kDampingFamilies,
      .defaults = default_of<NewmarkParams>,
      .validate = check,
      .implicit_coefficients = implicit,
      .reports_beta_gamma = true,
      .massless_dofs = kImplicitMasslessDofs,
  };
}

}  // namespace impactid
