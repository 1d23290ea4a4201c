// The Bathe composite scheme (core/methods/bathe_composite.hpp), a member of the composite
// family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

MethodValues values(const MethodParams& params) {
  MethodValues out;
  add_composite_weights(params, out);
  return out;
}

// ρ∞ = 0, γ = ½.
CompositeCoefficients composite(const MethodParams&) {
  return composite_step_coefficients(0.0, 0.5);
}

}  // namespace

MethodDescriptor bathe_method() {
  return {
      .kind = MethodKind::bathe,
      .name = "bathe",
      .summary =
          "Bathe composite (Bathe & Baig 2005, doi:10.1016/j.compstruc.2005.08.001): a "
          "trapezoidal sub-step to t + dt/2, then the 3-point backward Euler formula; "
          "implicit, second order, rho_inf = 0; contact enforced at both sub-steps",
      .parameters = {},
      .make = make_default<BatheParams>,
      .values = values,
      .choices = no_choices,
      .stages = 2,
      .spectrum = &kCompositeSpectrum,
      .same_parameters = same_composite_coefficients,
      .defaults = default_of<BatheParams>,
      .validate = no_check,
      .composite_coefficients = composite,
      .massless_dofs = kCompositeMasslessDofs,
  };
}

}  // namespace impactid
