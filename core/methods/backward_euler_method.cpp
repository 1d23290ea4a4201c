// Backward Euler (eqs 8-10), a member of the single-step implicit family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

ImplicitCoefficients implicit(const MethodParams&) {
  return ImplicitCoefficients{0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0};
}

}  // namespace

MethodDescriptor backward_euler_method() {
  return {
      .kind = MethodKind::backward_euler,
      .name = "backward-euler",
      .summary =
          "backward Euler (eqs 8-10): implicit, first order, unconditionally stable, "
          "strongly dissipative",
      .parameters = {},
      .make = make_default<BackwardEulerParams>,
      .values = no_values,
      .choices = no_choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .defaults = default_of<BackwardEulerParams>,
      .validate = no_check,
      .implicit_coefficients = implicit,
      .massless_dofs = kImplicitMasslessDofs,
  };
}

}  // namespace impactid
