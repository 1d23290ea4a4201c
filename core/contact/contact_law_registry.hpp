// One descriptor per contact law, which every layer loops over: the law's name as users write it,
// a one-line summary, the parameters it takes (their keys, units, defaults, ranges, docs and
// checks), and what distinguishes its behaviour where the code outside core/contact/ must know
// it (whether it acts through springs, whether the explicit methods apply it as an explicit
// force, whether it iterates). The command line's options and --help, plan keys and sweep axes,
// `impactid contact-laws`, `simulate`'s report and the Python module all come from here.
//
// Each law is defined in its own file (core/contact/lagrange_law.cpp, penalty_law.cpp,
// augmented_lagrangian_law.cpp, paoli_schatzman_law.cpp) with the parameters it introduces and its
// own arithmetic (the spring's k, Uzawa's iterations: penalty_law.hpp,
// augmented_lagrangian_law.hpp). The solves that the steppers call (one wall, two walls, a
// constraint list, the explicit stages, the explicit stable step) are in core/contact/ too
// (contact_treatment, constraint_list_law, ...); docs/architecture.md, "A contact law", lists what
// a new law touches.
//
// Whether a method refuses a law is the method's to say, not the law's: core/methods sits above
// core/contact and may name laws, not the other way round. A method says it through its
// descriptor's traits (MethodDescriptor::two_step_displacement, for a law with two_step_gap), which
// contact_law_refusal (core/methods/method_registry.hpp) reads.
//
// Thread safety: the registry is immutable; every function is reentrant.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/common/parameter_error.hpp"
#include "core/contact/contact_law.hpp"

namespace impactid {

/// A parameter of one or more laws, by the key used alike on the command line (with '-' for
/// '_'), in plan files, as a sweep axis and in HDF5 attributes.
struct ContactLawParameter {
  const char* name;         ///< snake_case key, the ContactTreatment field it sets
  bool integer;             ///< an integer; otherwise a real number
  const char* unit;         ///< "" when dimensionless
  const char* description;  ///< one line, with the laws taking it, the default and the range
  /// Sets the field; an integer's value is integral (the caller checks that).
  void (*assign)(ContactTreatment& treatment, double value);
  /// The field's value; NaN when it is not set (penalty_stiffness when the factor applies).
  double (*value)(const ContactTreatment& treatment);
  /// The range check, naming the key, the value and the constraint; nothing when valid.
  std::optional<ParameterError> (*check)(const ContactTreatment& treatment);
};

struct ContactLawDescriptor {
  ContactLaw law;
  const char* name;     ///< "penalty": on the command line, in plans and in HDF5 attributes
  const char* summary;  ///< one line: what it enforces and how
  /// The parameters this law introduces, defined in its file, in --help order.
  std::span<const ContactLawParameter> introduces;
  /// Every key it takes, its own and other laws' (the augmented Lagrangian's spring is the
  /// penalty's), in contact_law_parameters()' order.
  std::span<const char* const> parameters;
  /// It acts through springs of stiffness k: contacts penetrate by λ/k and are not snapped onto
  /// their walls; a run reports the penetration, the iterations and the explicit stable step.
  bool springs = false;
  /// The explicit methods apply its force k·max(0, g) of the displacement their equilibrium is
  /// taken at, without a solve: its springs shorten their stable step
  /// (core/contact/stable_step.hpp) and a step above it is flagged with a hint to lower the
  /// stiffness.
  bool explicit_force = false;
  /// Each contact solve is Uzawa's iterations, counted and capped (augmented_max_iterations); a
  /// run reports how many and how many steps ended at the cap.
  bool iterates = false;
  /// Its gap holds on (u_{n+1} + e·u_{n−1})/(1 + e), a position-level impact law with a
  /// coefficient of restitution e (Paoli–Schatzman): only a method whose step is a two-step
  /// recurrence in u (MethodDescriptor::two_step_displacement: central difference) takes it; the
  /// others refuse it by name (contact_law_refusal, core/methods/method_registry.hpp).
  bool two_step_gap = false;
};

/// Each law's descriptor, defined in its own file.
const ContactLawDescriptor& lagrange_law();
const ContactLawDescriptor& penalty_law();
const ContactLawDescriptor& augmented_lagrangian_law();
const ContactLawDescriptor& paoli_schatzman_law();

/// Every law, in the order --help and `impactid contact-laws` list them (the default first).
std::span<const ContactLawDescriptor> contact_law_registry();
const ContactLawDescriptor& descriptor(ContactLaw law);
const ContactLawDescriptor* find_contact_law(std::string_view name);
/// Every law's name, as "lagrange|penalty|augmented-lagrangian".
std::string contact_law_names();

/// Every law's parameter, each once, in the laws' order: the order of --help, plan errors and
/// validate().
std::span<const ContactLawParameter> contact_law_parameters();
const ContactLawParameter* find_contact_law_parameter(std::string_view name);
bool law_takes(const ContactLawDescriptor& law, std::string_view parameter);
/// The laws that take a parameter, as "penalty|augmented-lagrangian".
std::string contact_laws_taking(std::string_view parameter);

/// The law's name ("augmented-lagrangian"), and back; nothing for a name no law has.
const char* to_string(ContactLaw law);
std::optional<ContactLaw> contact_law_from_string(const std::string& name);

/// The first invalid parameter, in contact_law_parameters()' order, whatever the law (the reason
/// is ContactTreatment's), or nothing.
std::optional<ParameterError> validate(const ContactTreatment& treatment);

}  // namespace impactid
