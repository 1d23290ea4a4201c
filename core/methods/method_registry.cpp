#include "core/methods/method_registry.hpp"

#include <array>
#include <stdexcept>
#include <vector>

#include "core/contact/contact_law_registry.hpp"

namespace impactid {

// Each method's descriptor, built in its own file core/methods/<method>_method.cpp.
MethodDescriptor cdm_method();
MethodDescriptor backward_euler_method();
MethodDescriptor newmark_method();
MethodDescriptor hht_method();
MethodDescriptor generalized_alpha_method();
MethodDescriptor bathe_method();
MethodDescriptor rho_bathe_method();
MethodDescriptor tr_bdf2_method();
MethodDescriptor houbolt_method();
MethodDescriptor wilson_theta_method();
MethodDescriptor noh_bathe_method();
MethodDescriptor kim_explicit_method();
MethodDescriptor kr_alpha_method();

namespace {

constexpr std::array<MethodParameter, 10> kParameters{{
    {"delta", false,
     "delta of eq. 13: beta = (1+delta)^2/4, gamma = 1/2+delta (newmark: default 0.3; hht: default "
     "-alpha), >= 0",
     ""},
    {"alpha", false, "HHT alpha of eq. 14 (default -0.3), in [-0.5, 0]", ""},
    {"beta", false, "Newmark beta, given with gamma instead of delta (> 0)", ""},
    {"gamma", false, "Newmark gamma, given with beta instead of delta (>= 0)", ""},
    {"rho_inf", false,
     "high-frequency spectral radius (generalized-alpha: default 0.8; rho-bathe: default 0; "
     "kr-alpha: default 0.8), in [0, 1]",
     ""},
    {"substep_ratio", false,
     "rho-bathe sub-step ratio gamma: the trapezoidal sub-step ends at t + gamma*dt (default "
     "(2 - sqrt(2 + 2*rho_inf))/(1 - rho_inf), 1/2 at rho_inf = 1: equal effective matrices), "
     "in (0, 1)",
     ""},
    {"theta", false,
     "wilson-theta theta: equilibrium at t + theta*dt (default 1.4), >= (1+sqrt(3))/2 = 1.3660254 "
     "(unconditionally stable from there on)",
     ""},
    {"p", false,
     "noh-bathe sub-step ratio p: the first explicit sub-step ends at t + p*dt (default 0.54), in "
     "[0.5, 1); stable up to omega*dt = Omega_crit(p), 3.745 at 0.54; kim-explicit stage ratio p: "
     "its first stage ends at t + p*dt (default 1/2), in [1/3, 1/2]; stable up to Omega_crit(p), "
     "sqrt(6) at 1/2",
     ""},
    {"cdm_velocity", true,
     "central difference velocity: eq. 3 central or eq. 6/7 backward (default central)",
     "central|backward"},
    {"hht_contact", true,
     "where the contact force of an alpha-method acts: at t+dt (endpoint, default) or "
     "alpha-weighted",
     "endpoint|weighted"},
}};

// Room for the registered methods beside the built-in ones: the registry's storage is reserved
// once, so that descriptor references stay valid while methods are registered.
constexpr std::size_t kRegistryCapacity = 64;

// The registry: one line per built-in method, in MethodKind's order, then the registered ones.
// Built on first use, not at static initialisation: the descriptors come from other translation
// units, whose static order is unspecified.
std::vector<MethodDescriptor>& methods() {
  static std::vector<MethodDescriptor> registered = [] {
    std::vector<MethodDescriptor> out;
    out.reserve(kRegistryCapacity);
    for (MethodDescriptor m : {
             cdm_method(),
             backward_euler_method(),
             newmark_method(),
             hht_method(),
             generalized_alpha_method(),
             bathe_method(),
             rho_bathe_method(),
             tr_bdf2_method(),
             houbolt_method(),
             wilson_theta_method(),
             noh_bathe_method(),
             kim_explicit_method(),
             kr_alpha_method(),
         }) {
      out.push_back(m);
    }
    return out;
  }();
  return registered;
}

// A registered method's parameters carry its kind, which its own hooks cannot know (they are
// plain functions written before the registration handed the kind out): stamped here, where
// the library builds them.
MethodParams stamped(MethodParams params, MethodKind kind) {
  if (auto* registered = std::get_if<RegisteredMethodParams>(&params)) registered->kind = kind;
  return params;
}

std::string join(const auto& items, const auto& name_of) {
  std::string out;
  for (const auto& item : items) {
    if (!out.empty()) out += '|';
    out += name_of(item);
  }
  return out;
}

}  // namespace

void MethodArguments::set(std::string_view name, Value value) {
  for (auto& [key, v] : values_) {
    if (key == name) {
      v = std::move(value);
      return;
    }
  }
  values_.emplace_back(std::string(name), std::move(value));
}

const MethodArguments::Value* MethodArguments::find(std::string_view name) const {
  for (const auto& [key, v] : values_) {
    if (key == name) return &v;
  }
  return nullptr;
}

std::optional<double> MethodArguments::number(std::string_view name) const {
  const Value* v = find(name);
  if (!v || !std::holds_alternative<double>(*v)) return std::nullopt;
  return std::get<double>(*v);
}

std::optional<std::string> MethodArguments::choice(std::string_view name) const {
  const Value* v = find(name);
  if (!v || !std::holds_alternative<std::string>(*v)) return std::nullopt;
  return std::get<std::string>(*v);
}

std::span<const MethodParameter> method_parameters() {
  return kParameters;
}

const MethodParameter* find_method_parameter(std::string_view name) {
  for (const MethodParameter& p : kParameters) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

std::span<const MethodDescriptor> method_registry() {
  return methods();
}

const MethodDescriptor& descriptor(MethodKind kind) {
  for (const MethodDescriptor& m : methods()) {
    if (m.kind == kind) return m;
  }
  return methods().front();  // unreachable: every MethodKind is registered (a test checks)
}

const MethodDescriptor& descriptor(const MethodParams& params) {
  return descriptor(kind_of(params));
}

const char* to_string(MethodKind kind) {
  return descriptor(kind).name;
}

std::optional<MethodKind> method_kind_from_string(const std::string& name) {
  for (const MethodDescriptor& m : methods()) {
    if (name == m.name) return m.kind;
  }
  return std::nullopt;
}

bool method_takes(const MethodDescriptor& method, std::string_view parameter) {
  for (const char* name : method.parameters) {
    if (parameter == name) return true;
  }
  return false;
}

std::string methods_taking(std::string_view parameter) {
  std::string out;
  for (const MethodDescriptor& m : methods()) {
    if (!method_takes(m, parameter)) continue;
    if (!out.empty()) out += '|';
    out += m.name;
  }
  return out;
}

std::string method_names() {
  return join(methods(), [](const MethodDescriptor& m) { return m.name; });
}

std::optional<std::string> massless_refusal(const MethodDescriptor& method,
                                            double rayleigh_stiffness) {
  std::string takers;
  for (const MethodDescriptor& m : methods()) {
    if (m.massless_dofs) takers += (takers.empty() ? "" : "|") + std::string(m.name);
  }
  if (!method.massless_dofs) {
    return std::string("method ") + method.name +
           " does not step a mass matrix with massless contact DOFs (the methods that do: " +
           takers + ")";
  }
  if (method.massless_dofs_undamped && rayleigh_stiffness != 0.0) {
    return std::string("method ") + method.name +
           " steps massless contact DOFs only without stiffness-proportional damping "
           "(rayleigh_stiffness = " +
           format_value(rayleigh_stiffness) + ")";
  }
  return std::nullopt;
}

std::optional<std::string> contact_law_refusal(const MethodDescriptor& method, ContactLaw law) {
  const ContactLawDescriptor& d = descriptor(law);
  if (!d.two_step_gap || method.two_step_displacement) return std::nullopt;
  std::string takers;
  for (const MethodDescriptor& m : methods()) {
    if (m.two_step_displacement) takers += (takers.empty() ? "" : "|") + std::string(m.name);
  }
  return std::string("method ") + method.name + " does not take contact law " + d.name +
         " (its gap holds on a mean of u_{n+1} and u_{n-1}, which needs a two-step recurrence in "
         "u; the methods that take it: " +
         takers + ")";
}

std::variant<MethodParams, ParameterError> build_method(MethodKind kind,
                                                        const MethodArguments& given) {
  const MethodDescriptor& method = descriptor(kind);
  for (const MethodParameter& p : kParameters) {
    if (!given.has(p.name) || method_takes(method, p.name)) continue;
    const auto number = given.number(p.name);
    const std::string text = number ? format_value(*number) : *given.choice(p.name);
    return ParameterError{p.name, text,
                          std::string("is not a parameter of method ") + method.name +
                              " (it applies to " + methods_taking(p.name) + ")"};
  }
  auto made = method.make(given);
  if (auto* params = std::get_if<MethodParams>(&made)) *params = stamped(*params, kind);
  return made;
}

MethodParams default_params(MethodKind kind) {
  return stamped(descriptor(kind).defaults(), kind);
}

MethodKind register_method(MethodDescriptor method) {
  std::vector<MethodDescriptor>& registry = methods();
  const std::string name = method.name ? method.name : "";
  const auto refuse = [&](const std::string& why) {
    throw std::invalid_argument("register_method(\"" + name + "\"): " + why);
  };
  if (name.empty()) refuse("a method needs a name");
  if (method_kind_from_string(name)) refuse("the name is taken");
  if (!method.summary) refuse("a method needs a summary");
  if (!method.make || !method.values || !method.choices || !method.defaults || !method.validate ||
      !method.same_parameters || !method.spectrum) {
    refuse("make, values, choices, defaults, validate, same_parameters and spectrum are needed");
  }
  if (method.parameters.size() > RegisteredMethodParams::kMaxParameters) {
    refuse("takes more than " + std::to_string(RegisteredMethodParams::kMaxParameters) +
           " parameters");
  }
  for (const char* parameter : method.parameters) {
    const MethodParameter* p = find_method_parameter(parameter);
    if (!p || p->choice) refuse(std::string(parameter) + " is not a number key of the table");
  }
  // The steppers a registered method may use: the single-step implicit family's or the
  // composite schemes', chosen by the coefficients it gives (core/run/simulation.cpp).
  if (!method.implicit_coefficients == !method.composite_coefficients) {
    refuse("give exactly one of implicit_coefficients and composite_coefficients");
  }
  if (method.stepper) refuse("a registered method is stepped by those coefficients, not `stepper`");
  // A damping family's params() could not carry the kind (stamped() cannot reach it).
  if (!method.damping_families.empty()) refuse("damping families are for built-in methods");
  if (registry.size() == registry.capacity()) refuse("the registry is full");
  // The built-in methods fill the kinds before first_registered, one each, in order.
  method.kind = static_cast<MethodKind>(registry.size());
  registry.push_back(method);
  return method.kind;
}

std::optional<ParameterError> validate(const MethodParams& params) {
  return descriptor(params).validate(params);
}

bool is_single_step_implicit(const MethodParams& params) {
  return descriptor(params).implicit_coefficients != nullptr;
}

ImplicitCoefficients implicit_coefficients(const MethodParams& params) {
  const MethodDescriptor& method = descriptor(params);
  // Not a member: a placeholder, never stepped (callers dispatch those methods elsewhere).
  if (!method.implicit_coefficients) return {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  return method.implicit_coefficients(params);
}

bool is_composite(const MethodParams& params) {
  return descriptor(params).composite_coefficients != nullptr;
}

CompositeCoefficients composite_coefficients(const MethodParams& params) {
  const MethodDescriptor& method = descriptor(params);
  if (!method.composite_coefficients) return composite_step_coefficients(0.0, 0.5);  // Bathe's
  return method.composite_coefficients(params);
}

StepperCoefficients stepper_coefficients(const MethodParams& params) {
  const MethodDescriptor& method = descriptor(params);
  if (method.stepper) return method.stepper(params);
  if (method.composite_coefficients) return method.composite_coefficients(params);
  return implicit_coefficients(params);
}

std::optional<BetaGamma> reported_beta_gamma(const MethodParams& params) {
  if (!descriptor(params).reports_beta_gamma) return std::nullopt;
  const ImplicitCoefficients c = implicit_coefficients(params);
  return BetaGamma{c.b1, c.g1};
}

bool same_method_parameters(const MethodParams& a, const MethodParams& b) {
  return kind_of(a) == kind_of(b) && descriptor(a).same_parameters(a, b);
}

std::optional<double> reported_value(const MethodParams& params, std::string_view name) {
  for (const ReportedValue& v : descriptor(params).values(params)) {
    if (name == v.name) return v.value;
  }
  return std::nullopt;
}

}  // namespace impactid
