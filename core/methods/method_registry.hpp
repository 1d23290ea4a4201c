// One descriptor per time-stepping method, which every layer loops over: the method's name, the
// parameters a user may give it (their keys, docs, defaults and ranges), how the given ones build
// its parameter struct (core/methods/method.hpp), the values it reports (its parameters and the
// coefficients derived from them), its amplification matrix and stability data for the spectral
// analysis, when two of its parameter sets step alike, and its families of adjustable
// dissipation. The command line's options and --help, plan keys and sweep axes, `simulate`'s and
// `compare`'s reports, HDF5 attributes, work-precision columns, the spectral analysis, the
// references' cache and the damping-matched comparisons all come from here. Each method's
// descriptor is built in its own file, core/methods/<method>_method.cpp, and registered by one
// line of the list in method_registry.cpp (docs/architecture.md, "Adding a method").
//
// Keys are shared where the meaning is: `delta` is δ of eq. 13 for Newmark and HHT alike,
// `hht_contact` where an α-method's contact force acts. A key's description says what it is for
// each method that takes it.
//
// Thread safety: the registry is built on first use (thread-safe) and changes only by
// register_method(), which belongs to start-up; every other function is reentrant.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/contact/contact_law.hpp"
#include "core/methods/method.hpp"
#include "core/methods/stepper_coefficients.hpp"

namespace impactid {

/// A parameter a user may give a method, by the key used alike on the command line (with '-'
/// for '_'), in plan files, as a sweep axis and as an HDF5 attribute.
struct MethodParameter {
  const char* name;         ///< snake_case key
  bool choice;              ///< a word from `choices`; otherwise a real number
  const char* description;  ///< one line: meaning, default and range for each method taking it
  const char* choices;      ///< "central|backward" for a choice; "" for a number
};

/// Method parameters as given (unset ones take the method's defaults): numbers and choice words
/// by key, in the order they were set. A key set again replaces its value.
class MethodArguments {
 public:
  using Value = std::variant<double, std::string>;

  void set(std::string_view name, Value value);
  bool has(std::string_view name) const { return find(name) != nullptr; }
  std::optional<double> number(std::string_view name) const;
  std::optional<std::string> choice(std::string_view name) const;
  const std::vector<std::pair<std::string, Value>>& values() const { return values_; }

  bool operator==(const MethodArguments&) const = default;

 private:
  const Value* find(std::string_view name) const;
  std::vector<std::pair<std::string, Value>> values_;
};

/// A number a method reports of itself: one of its parameters, or a coefficient derived from
/// them (β and γ of eq. 13, generalized-α's α_m and α_f).
struct ReportedValue {
  const char* name;
  double value;
  bool derived;  ///< not a parameter the user gave or could give this method
};

struct MethodSpectrum;  // core/methods/method_spectrum.hpp

/// A one-parameter family of a method whose algorithmic dissipation grows with the parameter:
/// what a damping-matched comparison (study/studies/damping_match.hpp) searches.
struct MethodDampingFamily {
  const char* name;       ///< "newmark", "hht-eq19", …: unique over all methods
  const char* label;      ///< for tables: "hht (delta = -1.5*alpha)"
  const char* parameter;  ///< the plan/CLI key of the varied parameter: "delta", "alpha", …
  /// The searched range, from the end without algorithmic damping (ξ̄ = 0: δ = 0, α = 0,
  /// ρ∞ = 1) to the most dissipative end.
  double undamped_end, damped_end;
  /// The method's parameters at a value of the varied parameter.
  MethodParams (*params)(double parameter);
  /// Those parameters by their plan keys, as `impactid spectral --match-damping` reports them;
  /// nullptr (the default) when the varied parameter is the only one: {{parameter, value}}.
  std::vector<std::pair<const char*, double>> (*parameters)(double parameter) = nullptr;
};

struct MethodDescriptor {
  MethodKind kind;
  const char* name;     ///< "hht": the name on the command line, in plans and in HDF5
  const char* summary;  ///< one line: what it is, its order and dissipation, its paper
  /// The keys of method_parameters() this method takes, in that table's order.
  std::span<const char* const> parameters;
  /// Builds the method's parameters from the given ones, each a key it takes (build_method
  /// checks that first). Errors name the key: a missing partner (Newmark's β without γ), a
  /// combination that is not allowed. Ranges are validate()'s (core/methods/method.hpp).
  std::variant<MethodParams, ParameterError> (*make)(const MethodArguments& given);
  /// Its numbers in report order: parameters, then derived coefficients.
  std::vector<ReportedValue> (*values)(const MethodParams& params);
  /// Its choice parameters' values as words, in parameters' order.
  std::vector<std::pair<const char*, std::string>> (*choices)(const MethodParams& params);
  /// The stages of one step: solves of an implicit method, force evaluations of an explicit
  /// one (two for the composite schemes and the two-stage explicit ones). The unit of issue
  /// 19's speed bound, "no method more than 2.5× HHT's batched time per dof-step per stage".
  int stages = 1;
  /// Its amplification matrix and stability data for the spectral analysis.
  const MethodSpectrum* spectrum = nullptr;
  /// Whether two parameter sets of this method step alike (equal derived coefficients where
  /// they are derived: HHT with δ unset equals HHT with δ = −α).
  bool (*same_parameters)(const MethodParams& a, const MethodParams& b) = nullptr;
  /// Its families of adjustable dissipation, in the order damping matches list them; none when
  /// its dissipation is fixed (backward Euler, central difference, …).
  std::span<const MethodDampingFamily> damping_families = {};
  /// Its default parameters (the defaults of its parameter struct).
  MethodParams (*defaults)() = nullptr;
  /// The first invalid field of its parameters ("delta", "rho_inf", …), or nothing.
  std::optional<ParameterError> (*validate)(const MethodParams& params) = nullptr;
  /// Its coefficients as a member of the single-step implicit family (ImplicitCoefficients),
  /// what ImplicitIntegrator and the batched kernels step alone; null for the others.
  ImplicitCoefficients (*implicit_coefficients)(const MethodParams& params) = nullptr;
  /// Its two sub-steps' coefficients as a composite scheme (core/methods/bathe_composite.hpp);
  /// null for the others.
  CompositeCoefficients (*composite_coefficients)(const MethodParams& params) = nullptr;
  /// The stepper that runs it, with its coefficients (core/methods/stepper_coefficients.hpp); null
  /// when implicit_coefficients or composite_coefficients say it (their families' steppers).
  StepperCoefficients (*stepper)(const MethodParams& params) = nullptr;
  /// Whether reports show the β and γ of its implicit_coefficients (the Newmark family:
  /// Newmark, HHT, generalized-α).
  bool reports_beta_gamma = false;
  /// What the stable step a run of it certifies is based on ("Omega_crit(p) over the bound on
  /// omega_max"), for `simulate`'s report; null when its runs certify none. The certificate
  /// needs a diagonal mass.
  const char* stable_step = nullptr;
  /// How it steps a DOF without mass (the contact DOFs of mass = redistributed|singular,
  /// core/model/rod_scene.hpp), one line for `impactid methods`; null (the default) when it does
  /// not, and a run of it on such a mass is refused by name before it starts (study/plan/
  /// simulation_settings.cpp: build(); simulate() too, as a failed run).
  const char* massless_dofs = nullptr;
  /// It steps massless DOFs only without stiffness-proportional damping (rayleigh_stiffness = 0),
  /// which would put their velocity into their static equation.
  bool massless_dofs_undamped = false;
  /// Its step is a two-step recurrence in u (u_{n+1} from u_n and u_{n−1}: central difference),
  /// so it takes a contact law whose gap holds on a mean of u_{n+1} and u_{n−1}
  /// (ContactLawDescriptor::two_step_gap: Paoli–Schatzman's); a method without it refuses such a
  /// law by name (contact_law_refusal).
  bool two_step_displacement = false;
};

/// Why `method` does not step a mass matrix with massless DOFs under the given stiffness-
/// proportional damping (its descriptor's massless_dofs), or nothing if it does.
std::optional<std::string> massless_refusal(const MethodDescriptor& method,
                                            double rayleigh_stiffness);

/// Why `method` does not take the contact law `law` (a law with two_step_gap needs a method with
/// two_step_displacement), or nothing if it does.
std::optional<std::string> contact_law_refusal(const MethodDescriptor& method, ContactLaw law);

/// Every method parameter's key, in the order --help and plan errors list them.
std::span<const MethodParameter> method_parameters();
const MethodParameter* find_method_parameter(std::string_view name);

/// Every method, in the order `compare` and --help list them.
std::span<const MethodDescriptor> method_registry();
const MethodDescriptor& descriptor(MethodKind kind);
const MethodDescriptor& descriptor(const MethodParams& params);

bool method_takes(const MethodDescriptor& method, std::string_view parameter);
/// The methods that take a parameter, as "newmark|hht".
std::string methods_taking(std::string_view parameter);
/// Every method's name, as "cdm|backward-euler|…".
std::string method_names();

/// Adds a method written outside the library (docs/architecture.md, "A method outside the
/// library") and returns the kind it is known by from then on: `simulate`, sweeps, plans (by its
/// name), the references and the spectral analysis take it as they take a built-in method. Its
/// parameters are RegisteredMethodParams (the library stamps its kind into them); its
/// `parameters` are number keys of method_parameters(), at most
/// RegisteredMethodParams::kMaxParameters; it is stepped as a member of the single-step implicit
/// family or as a composite scheme, by the coefficients it gives (exactly one of
/// implicit_coefficients and composite_coefficients; no `stepper`, since the other steppers take
/// their own methods' parameters); it has no damping families. The descriptor's
/// `kind` is ignored. Throws std::invalid_argument naming the method and what is missing.
/// Register at start-up, before any thread reads the registry: registration is not synchronised
/// with readers.
MethodKind register_method(MethodDescriptor method);

/// The parameters of `kind` from the given ones: a key the method does not take is an error
/// ("is not a parameter of method cdm (it applies to newmark|hht)"), checked in
/// method_parameters()' order; then the descriptor's make(). Not range-checked: validate().
std::variant<MethodParams, ParameterError> build_method(MethodKind kind,
                                                        const MethodArguments& given);

/// Whether a and b are the same method with parameters that step alike (the descriptor's
/// same_parameters).
bool same_method_parameters(const MethodParams& a, const MethodParams& b);

/// The value `params` reports under `name` (a parameter or a derived coefficient), if any.
std::optional<double> reported_value(const MethodParams& params, std::string_view name);

}  // namespace impactid
