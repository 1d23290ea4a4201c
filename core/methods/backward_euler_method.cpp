// Backward Euler (eqs 8-10), a member of the single-step implicit family: its descriptor.
#include "core/methods/method_families.hpp"

namespace impactid {
namespace {

MadeMethod make(const MethodArguments&) {
  return BackwardEulerParams{};
}

MethodParams defaults() {
  return BackwardEulerParams{};
}

std::optional<ParameterError> check(const MethodParams&) {
  return {};
}

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
      .make = make,
      .values = no_values,
      .choices = no_choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .defaults = defaults,
      .validate = check,
      .implicit_coefficients = implicit,
  };
}

}  // namespace impactid
