// What steps a method: one stepper (core/run/steppers.hpp) and the coefficients it takes from the
// method's parameters. A method names its stepper by the coefficients its descriptor gives
// (core/methods/method_registry.hpp: `stepper`, or implicit_coefficients / composite_coefficients
// for the two families many methods share), and the run, the batched kernels' eligibility and
// their set-up dispatch on those coefficients' type: on the stepper, never on the method. So a
// new method that an existing stepper can step costs its own file and one registration line; a
// new stepper adds an alternative here and the places that visit it (docs/architecture.md,
// "Adding a method").
#pragma once

#include <variant>

#include "core/methods/method.hpp"

namespace impactid {

/// Central difference's one choice: the velocity it reports (core/methods/central_difference.hpp).
struct CentralDifferenceCoefficients {
  CdmVelocity velocity;
};

/// One alternative per stepper: the single-step implicit family (ImplicitIntegrator), the
/// composite schemes, Houbolt, Wilson-θ, central difference, the two-stage explicit schemes of Noh
/// and Bathe and of Kim, and KR-α.
using StepperCoefficients =
    std::variant<ImplicitCoefficients, CompositeCoefficients, HouboltCoefficients,
                 WilsonThetaCoefficients, CentralDifferenceCoefficients, NohBatheCoefficients,
                 KimExplicitCoefficients, KrAlphaCoefficients>;

/// The stepper of `params`' method and its coefficients, from the method's descriptor.
StepperCoefficients stepper_coefficients(const MethodParams& params);

/// Whether `params`' method is stepped by the stepper of `Coefficients`.
template <class Coefficients>
bool stepped_by(const MethodParams& params) {
  return std::holds_alternative<Coefficients>(stepper_coefficients(params));
}

}  // namespace impactid
