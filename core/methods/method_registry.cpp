#include "core/methods/method_registry.hpp"

#include <array>

namespace impactid {
namespace {

using Values = std::vector<ReportedValue>;
using Choices = std::vector<std::pair<const char*, std::string>>;
using Made = std::variant<MethodParams, ParameterError>;

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

// β and γ of a member of the Newmark family, derived (from δ, α or ρ∞) unless given.
void add_beta_gamma(const MethodParams& params, bool derived, Values& out) {
  const BetaGamma bg = *reported_beta_gamma(params);
  out.push_back({"beta", bg.beta, derived});
  out.push_back({"gamma", bg.gamma, derived});
}

// --- central difference ---
constexpr const char* kCdmParameters[] = {"cdm_velocity"};
// A choice word given programmatically is checked here too (assign() checks the user's).
ParameterError bad_choice(const char* name, const std::string& word) {
  return ParameterError{name, word,
                        std::string("must be one of ") + find_method_parameter(name)->choices};
}

Made make_cdm(const MethodArguments& given) {
  CentralDifferenceParams p;
  if (const auto word = given.choice("cdm_velocity")) {
    const auto velocity = cdm_velocity_from_string(*word);
    if (!velocity) return bad_choice("cdm_velocity", *word);
    p.velocity = *velocity;
  }
  return p;
}
Values cdm_values(const MethodParams&) {
  return {};
}
Choices cdm_choices(const MethodParams& params) {
  return {{"cdm_velocity", to_string(std::get<CentralDifferenceParams>(params).velocity)}};
}

// --- backward Euler ---
Made make_backward_euler(const MethodArguments&) {
  return BackwardEulerParams{};
}
Values no_values(const MethodParams&) {
  return {};
}
Choices no_choices(const MethodParams&) {
  return {};
}

// --- Newmark ---
constexpr const char* kNewmarkParameters[] = {"delta", "beta", "gamma"};
Made make_newmark(const MethodArguments& given) {
  NewmarkParams p;
  const auto delta = given.number("delta"), beta = given.number("beta"),
             gamma = given.number("gamma");
  if (beta || gamma) {
    if (delta) {
      return ParameterError{"delta", format_value(*delta),
                            "cannot be given with beta and gamma (eq. 13 derives them)"};
    }
    if (!beta) return ParameterError{"beta", "(missing)", "must be given with gamma"};
    if (!gamma) return ParameterError{"gamma", "(missing)", "must be given with beta"};
    p.coefficients = BetaGamma{*beta, *gamma};
  } else if (delta) {
    p.delta = *delta;
  }
  return p;
}
Values newmark_values(const MethodParams& params) {
  const auto& p = std::get<NewmarkParams>(params);
  Values out;
  if (!p.coefficients) out.push_back({"delta", p.delta, false});
  add_beta_gamma(params, !p.coefficients, out);
  return out;
}

// hht_contact of an α-method, when given.
std::optional<ParameterError> read_contact(const MethodArguments& given,
                                           ContactWeighting& contact) {
  const auto word = given.choice("hht_contact");
  if (!word) return std::nullopt;
  const auto value = contact_weighting_from_string(*word);
  if (!value) return bad_choice("hht_contact", *word);
  contact = *value;
  return std::nullopt;
}

// --- HHT-α ---
constexpr const char* kHhtParameters[] = {"delta", "alpha", "hht_contact"};
Made make_hht(const MethodArguments& given) {
  HhtParams p;
  if (const auto alpha = given.number("alpha")) p.alpha = *alpha;
  p.delta = given.number("delta");
  if (auto e = read_contact(given, p.contact)) return *e;
  return p;
}
Values hht_values(const MethodParams& params) {
  const auto& p = std::get<HhtParams>(params);
  Values out{{"delta", p.delta.value_or(-p.alpha), false}, {"alpha", p.alpha, false}};
  add_beta_gamma(params, true, out);
  return out;
}
Choices hht_choices(const MethodParams& params) {
  return {{"hht_contact", to_string(std::get<HhtParams>(params).contact)}};
}

// --- generalized-α ---
constexpr const char* kGeneralizedAlphaParameters[] = {"rho_inf", "hht_contact"};
Made make_generalized_alpha(const MethodArguments& given) {
  GeneralizedAlphaParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  if (auto e = read_contact(given, p.contact)) return *e;
  return p;
}
Values generalized_alpha_values(const MethodParams& params) {
  Values out{{"rho_inf", std::get<GeneralizedAlphaParams>(params).rho_inf, false}};
  add_beta_gamma(params, true, out);
  // Derived from ρ∞ (Chung & Hulbert 1993), as β and γ are.
  const ImplicitCoefficients c = implicit_coefficients(params);
  out.push_back({"alpha_m", c.alpha_m, true});
  out.push_back({"alpha_f", c.alpha_f, true});
  return out;
}
Choices generalized_alpha_choices(const MethodParams& params) {
  return {{"hht_contact", to_string(std::get<GeneralizedAlphaParams>(params).contact)}};
}

// --- the Bathe family (composite: core/methods/bathe_composite.hpp) ---
// The second sub-step's weights q0, q1, q2 (derived), after the parameters.
void add_composite_weights(const MethodParams& params, Values& out) {
  const CompositeCoefficients c = composite_coefficients(params);
  out.push_back({"q0", c.q0, true});
  out.push_back({"q1", c.q1, true});
  out.push_back({"q2", c.q2, true});
}
Made make_bathe(const MethodArguments&) {
  return BatheParams{};
}
Made make_tr_bdf2(const MethodArguments&) {
  return TrBdf2Params{};
}
Values bathe_values(const MethodParams& params) {
  Values out;
  add_composite_weights(params, out);
  return out;
}
constexpr const char* kRhoBatheParameters[] = {"rho_inf", "substep_ratio"};
Made make_rho_bathe(const MethodArguments& given) {
  RhoBatheParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  p.gamma = given.number("substep_ratio");
  return p;
}
Values rho_bathe_values(const MethodParams& params) {
  const auto& p = std::get<RhoBatheParams>(params);
  Values out{{"rho_inf", p.rho_inf, false},
             {"substep_ratio", composite_coefficients(params).gamma, false}};
  add_composite_weights(params, out);
  return out;
}

// --- Houbolt and Wilson-θ (core/methods/houbolt.hpp, core/methods/wilson_theta.hpp) ---
Made make_houbolt(const MethodArguments&) {
  return HouboltParams{};
}
constexpr const char* kWilsonThetaParameters[] = {"theta"};
Made make_wilson_theta(const MethodArguments& given) {
  WilsonThetaParams p;
  if (const auto theta = given.number("theta")) p.theta = *theta;
  return p;
}
Values wilson_theta_values(const MethodParams& params) {
  return {{"theta", std::get<WilsonThetaParams>(params).theta, false}};
}

// --- Noh–Bathe explicit (core/methods/noh_bathe.hpp) ---
constexpr const char* kNohBatheParameters[] = {"p"};
Made make_noh_bathe(const MethodArguments& given) {
  NohBatheParams p;
  if (const auto value = given.number("p")) p.p = *value;
  return p;
}
// p, then the velocity weights and the stability limit Ω_crit(p) (derived).
Values noh_bathe_values(const MethodParams& params) {
  const auto& p = std::get<NohBatheParams>(params);
  const NohBatheCoefficients c = noh_bathe_coefficients(p);
  return {{"p", p.p, false},
          {"q0", c.q0, true},
          {"q1", c.q1, true},
          {"q2", c.q2, true},
          {"omega_crit", noh_bathe_critical_omega(p.p), true}};
}

// --- Kim's two-stage explicit scheme (core/methods/kim_explicit.hpp) ---
constexpr const char* kKimExplicitParameters[] = {"p"};
Made make_kim_explicit(const MethodArguments& given) {
  KimExplicitParams p;
  if (const auto value = given.number("p")) p.p = *value;
  return p;
}
// p, then the stability limit Ω_crit(p) (derived).
Values kim_explicit_values(const MethodParams& params) {
  const auto& p = std::get<KimExplicitParams>(params);
  return {{"p", p.p, false}, {"omega_crit", kim_explicit_critical_omega(p.p), true}};
}

// --- KR-α explicit (core/methods/kr_alpha.hpp) ---
constexpr const char* kKrAlphaParameters[] = {"rho_inf"};
Made make_kr_alpha(const MethodArguments& given) {
  KrAlphaParams p;
  if (const auto rho_inf = given.number("rho_inf")) p.rho_inf = *rho_inf;
  return p;
}
// ρ∞, then the scalars the matrices α1, α2, α3 are built from (derived).
Values kr_alpha_values(const MethodParams& params) {
  const auto& p = std::get<KrAlphaParams>(params);
  const KrAlphaCoefficients c = kr_alpha_coefficients(p);
  return {{"rho_inf", p.rho_inf, false},
          {"alpha_m", c.alpha_m, true},
          {"alpha_f", c.alpha_f, true},
          {"beta", c.beta, true},
          {"gamma", c.gamma, true}};
}

// The registry: one entry per method, in MethodKind's order.
const std::array<MethodDescriptor, 13> kMethods{{
    {MethodKind::central_difference, "cdm",
     "central difference with Carpenter's forward-increment multiplier (eqs 1-7; Carpenter, Taylor "
     "& Katona 1991, doi:10.1002/nme.1620320107): explicit, second order, no numerical "
     "dissipation, stable below Courant 1 with a lumped mass",
     kCdmParameters, make_cdm, cdm_values, cdm_choices},
    {MethodKind::backward_euler,
     "backward-euler",
     "backward Euler (eqs 8-10): implicit, first order, unconditionally stable, strongly "
     "dissipative",
     {},
     make_backward_euler,
     no_values,
     no_choices},
    {MethodKind::newmark, "newmark",
     "Newmark (eqs 11-13; Newmark 1959, doi:10.1061/JMCEA3.0000098): implicit, second order only "
     "at delta = 0 (trapezoidal rule), dissipative for delta > 0",
     kNewmarkParameters, make_newmark, newmark_values, no_choices},
    {MethodKind::hht, "hht",
     "HHT-alpha (eq. 14; Hilber, Hughes & Taylor 1977, doi:10.1002/eqe.4290050306): implicit, "
     "second order at delta = -alpha, high-frequency spectral radius (1+alpha)/(1-alpha) for alpha "
     "in [-1/3, 0]",
     kHhtParameters, make_hht, hht_values, hht_choices},
    {MethodKind::generalized_alpha, "generalized-alpha",
     "generalized-alpha (Chung & Hulbert 1993, doi:10.1115/1.2900803): implicit, second order, "
     "high-frequency spectral radius rho_inf with least low-frequency dissipation",
     kGeneralizedAlphaParameters, make_generalized_alpha, generalized_alpha_values,
     generalized_alpha_choices},
    {MethodKind::bathe,
     "bathe",
     "Bathe composite (Bathe & Baig 2005, doi:10.1016/j.compstruc.2005.08.001): a trapezoidal "
     "sub-step to t + dt/2, then the 3-point backward Euler formula; implicit, second order, "
     "rho_inf = 0; contact enforced at both sub-steps",
     {},
     make_bathe,
     bathe_values,
     no_choices,
     2},
    {MethodKind::rho_bathe, "rho-bathe",
     "rho_inf-Bathe composite (Noh & Bathe 2019, doi:10.1016/j.compstruc.2018.11.001): a "
     "trapezoidal sub-step to t + gamma*dt, then a 3-point formula; implicit, second order, "
     "high-frequency spectral radius rho_inf; contact enforced at both sub-steps",
     kRhoBatheParameters, make_rho_bathe, rho_bathe_values, no_choices, 2},
    {MethodKind::tr_bdf2,
     "tr-bdf2",
     "TR-BDF2 (Bank et al. 1985, doi:10.1109/T-ED.1985.22232), gamma = 2 - sqrt(2): a trapezoidal "
     "sub-step, then BDF2; implicit, second order, L-stable; rho-bathe's default (rho_inf = 0); "
     "contact enforced at both sub-steps",
     {},
     make_tr_bdf2,
     bathe_values,
     no_choices,
     2},
    {MethodKind::houbolt,
     "houbolt",
     "Houbolt (Houbolt 1950, doi:10.2514/8.1722): backward differences of the cubic through four "
     "displacements; implicit, three-step, second order, rho_inf = 0, dissipative at every "
     "frequency; started by the same cubic on the initial velocity and acceleration",
     {},
     make_houbolt,
     no_values,
     no_choices},
    {MethodKind::wilson_theta, "wilson-theta",
     "Wilson-theta (Wilson, Farhoomand & Bathe 1972, doi:10.1002/eqe.4290010305): linear "
     "acceleration extended to t + theta*dt, equilibrium there; implicit, second order, "
     "unconditionally stable for theta >= 1.366, rho_inf 0.78 at theta = 1.4; contact enforced "
     "at t + dt",
     kWilsonThetaParameters, make_wilson_theta, wilson_theta_values, no_choices},
    {MethodKind::noh_bathe, "noh-bathe",
     "Noh-Bathe explicit (Noh & Bathe 2013, doi:10.1016/j.compstruc.2013.06.007): two explicit "
     "sub-steps, to t + p*dt and t + dt; second order, dissipative for p > 1/2, stable up to "
     "omega*dt = Omega_crit(p) (3.745 at p = 0.54); contact enforced at both sub-steps",
     kNohBatheParameters, make_noh_bathe, noh_bathe_values, no_choices, 2},
    {MethodKind::kim_explicit, "kim-explicit",
     "Kim two-stage explicit (Kim 2019, IJNME 120:1-28, doi:10.1002/nme.6098; not the rho_b scheme "
     "of Kim 2019, Eng. Struct. 195:358-372, ref. 17 of Serfozo & Pere 2022): stages at t + p*dt "
     "and t + dt, then a quadratic correction of the end values; second order, period error "
     "O(Omega^4), stable up to omega*dt = Omega_crit(p) (sqrt(6) at p = 1/2); contact enforced at "
     "both stages",
     kKimExplicitParameters, make_kim_explicit, kim_explicit_values, no_choices, 2},
    {MethodKind::kr_alpha, "kr-alpha",
     "KR-alpha explicit (Kolay & Ricles 2014, doi:10.1002/eqe.2401): explicit displacement and "
     "velocity through the model-based matrices alpha1, alpha2, alpha3, generalized-alpha's "
     "equilibrium; second order, unconditionally stable (linear systems), high-frequency "
     "spectral radius rho_inf; contact enforced as a forward increment",
     kKrAlphaParameters, make_kr_alpha, kr_alpha_values, no_choices},
}};

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
  return kMethods;
}

const MethodDescriptor& descriptor(MethodKind kind) {
  for (const MethodDescriptor& m : kMethods) {
    if (m.kind == kind) return m;
  }
  return kMethods.front();  // unreachable: every MethodKind is registered (a test checks)
}

const MethodDescriptor& descriptor(const MethodParams& params) {
  return descriptor(kind_of(params));
}

const char* to_string(MethodKind kind) {
  return descriptor(kind).name;
}

std::optional<MethodKind> method_kind_from_string(const std::string& name) {
  for (const MethodDescriptor& m : kMethods) {
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
  for (const MethodDescriptor& m : kMethods) {
    if (!method_takes(m, parameter)) continue;
    if (!out.empty()) out += '|';
    out += m.name;
  }
  return out;
}

std::string method_names() {
  return join(kMethods, [](const MethodDescriptor& m) { return m.name; });
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

std::optional<double> reported_value(const MethodParams& params, std::string_view name) {
  for (const ReportedValue& v : descriptor(params).values(params)) {
    if (name == v.name) return v.value;
  }
  return std::nullopt;
}

}  // namespace impactid
