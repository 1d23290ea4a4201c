#include "core/methods/method_registry.hpp"

#include <array>

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

// The registry: one line per method, in MethodKind's order. Built on first use, not at static
// initialisation: the descriptors come from other translation units, whose static order is
// unspecified.
const auto& methods() {
  static const auto registered = std::to_array<MethodDescriptor>({
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
  });
  return registered;
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
  return method.make(given);
}

MethodParams default_params(MethodKind kind) {
  return descriptor(kind).defaults();
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
