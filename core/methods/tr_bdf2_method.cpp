// TR-BDF2 (core/methods/bathe_composite.hpp), a member of the composite family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

MethodValues values(const MethodParams& params) {
  MethodValues out;
  add_composite_weights(params, out);
  return out;
}

// ρ∞ = 0, γ = 2 − √2.
CompositeCoefficients composite(const MethodParams&) {
  return composite_step_coefficients(0.0, rho_bathe_default_gamma(0.0));
}

}  // namespace

MethodDescriptor tr_bdf2_method() {
  return {
      .kind = MethodKind::tr_bdf2,
      .name = "tr-bdf2",
      .summary =
          "TR-BDF2 (Bank et al. 1985, doi:10.1109/T-ED.1985.22232), gamma = 2 - sqrt(2): a "
          "trapezoidal sub-step, then BDF2; implicit, second order, L-stable; rho-bathe's "
          "default (rho_inf = 0); contact enforced at both sub-steps",
      .parameters = {},
      .make = make_default<TrBdf2Params>,
      .values = values,
      .choices = no_choices,
      .stages = 2,
      .spectrum = &kCompositeSpectrum,
      .same_parameters = same_composite_coefficients,
      .defaults = default_of<TrBdf2Params>,
      .validate = no_check,
      .composite_coefficients = composite,
      .massless_dofs = kCompositeMasslessDofs,
  };
}

}  // namespace impactid
