// What several methods share, for their own files (core/methods/<method>_method.cpp): helpers of
// their descriptors' make/values/choices, and the hooks of the two families whose members differ
// only in coefficients, the single-step implicit family (backward Euler, Newmark, HHT,
// generalized-α: ImplicitCoefficients) and the composite family (Bathe, ρ∞-Bathe, TR-BDF2:
// CompositeCoefficients).
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/methods/method_registry.hpp"
#include "core/methods/method_spectrum.hpp"

namespace impactid {

using MethodValues = std::vector<ReportedValue>;
using MethodChoices = std::vector<std::pair<const char*, std::string>>;
using MadeMethod = std::variant<MethodParams, ParameterError>;

MethodValues no_values(const MethodParams& params);
MethodChoices no_choices(const MethodParams& params);
/// defaults of every method: its parameter struct as its fields' initialisers give it.
template <class Params>
MethodParams default_of() {
  return Params{};
}
/// make of a method without parameters (build_method has checked that none was given).
template <class Params>
MadeMethod make_default(const MethodArguments&) {
  return Params{};
}
/// validate of a method whose parameters have no range to check (or none at all).
inline std::optional<ParameterError> no_check(const MethodParams&) {
  return std::nullopt;
}
/// same_parameters of a method without parameters: two of its sets always step alike.
bool always_same(const MethodParams& a, const MethodParams& b);

/// A choice word given programmatically is checked here too (assign() checks the user's).
ParameterError bad_choice(const char* name, const std::string& word);
/// hht_contact of an α-method, when given.
std::optional<ParameterError> read_contact(const MethodArguments& given, ContactWeighting& contact);
/// β and γ of a member of the Newmark family, derived (from δ, α or ρ∞) unless given.
void add_beta_gamma(const MethodParams& params, bool derived, MethodValues& out);
/// The second sub-step's weights q0, q1, q2 of a composite method (derived).
void add_composite_weights(const MethodParams& params, MethodValues& out);

/// The largest finite double: the upper end of an unbounded range check.
inline constexpr double kFiniteMax = std::numeric_limits<double>::max();

/// A member of the Newmark family (β, γ) with the α-method's α_m, α_f and contact weighting.
ImplicitCoefficients newmark_family(BetaGamma bg, double alpha_m, double alpha_f,
                                    ContactWeighting contact);

struct GeneralizedAlphaCoefficients {
  double alpha_m, alpha_f;
  BetaGamma bg;
};
/// Chung & Hulbert 1993, eqs 25 and 17: generalized-α's and KR-α's scalars from ρ∞.
GeneralizedAlphaCoefficients generalized_alpha_from_rho_inf(double rho_inf);

/// The linear-acceleration member (Newmark β = 1/6, γ = ½): Houbolt's first step, Wilson-θ's
/// extended step.
inline constexpr ImplicitCoefficients kLinearAcceleration{1.0 / 3.0, 1.0 / 6.0, 0.5, 0.5,
                                                          0.0,       0.0,       1.0};

/// The single-step implicit family: amplification from implicit_coefficients(), ρ∞ in closed
/// form, parameters equal when their coefficients are.
extern const MethodSpectrum kSingleStepImplicitSpectrum;
bool same_implicit_coefficients(const MethodParams& a, const MethodParams& b);

/// How the single-step implicit family steps a massless DOF (MethodDescriptor::massless_dofs).
inline constexpr const char* kImplicitMasslessDofs =
    "its effective matrix (1-alpha_m)*M + (1-alpha_f)*(b1*dt^2*K + ...) stays regular: a massless "
    "DOF satisfies its static equation (alpha_f-weighted) with the contact at every step; its "
    "initial acceleration is that of the static equation differentiated twice";

/// How the composite family and Houbolt step a massless DOF: each of their solves is an
/// ImplicitIntegrator's, whose effective matrix keeps the DOF's stiffness. (Wilson-θ is refused:
/// with the DOF's static equation at t + θΔt and the contact at t + Δt its runs on the rod grow
/// unstable.)
inline constexpr const char* kCompositeMasslessDofs =
    "each sub-step's effective matrix keeps its stiffness and stays regular: a massless DOF "
    "satisfies its static equation with the contact at every sub-step (the single-step family's "
    "rule for its initial acceleration)";
inline constexpr const char* kHouboltMasslessDofs =
    "its start and its steady step solve effective matrices that keep its stiffness: a massless "
    "DOF satisfies its static equation with the contact at every step";

/// The composite family: amplification of both sub-steps from composite_coefficients(), ρ∞
/// evaluated at Ω = 1e8, parameters equal when both sub-steps' coefficients are.
extern const MethodSpectrum kCompositeSpectrum;
bool same_composite_coefficients(const MethodParams& a, const MethodParams& b);

}  // namespace impactid
