#include "study/plan/simulation_settings.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <deque>
#include <string>
#include <type_traits>

#include "core/contact/contact_law_registry.hpp"
#include "core/reference/model_reference.hpp"
#include "study/plan/scene_path.hpp"

namespace impactid {
namespace {

using G = ParameterGroup;
using K = ParameterKind;

// The scene's keys (the one-body rod's, and those every scene takes), with the contact law and its
// parameters (from core/contact/contact_law_registry.hpp) after `mass`, then the method and its
// parameters (from core/methods/method_registry.hpp), then the output's.
constexpr ParameterInfo kSceneParameters[] = {

    {"length", G::scene, K::real, "mm", "rod length L (default 20, > 0)", "", ""},
    {"elements", G::scene, K::integer, "", "number of 2-node truss elements n (default 200, >= 1)",
     "", ""},
    {"youngs_modulus", G::scene, K::real, "MPa", "Young's modulus E (default 90, > 0)", "", ""},
    {"density", G::scene, K::real, "t/mm^3", "density rho (default 7.85e-9, > 0)", "", ""},
    {"area", G::scene, K::real, "mm^2", "cross-section A (default 1, > 0)", "", ""},
    {"velocity", G::scene, K::real, "mm/s", "initial velocity v0 toward the wall (default 1000)",
     "", ""},
    {"gap", G::scene, K::real, "mm", "initial gap to the wall (default 0.01, >= 0)", "", ""},
    {"far_gap", G::scene, K::real, "mm",
     "gap between node 0 and a second rigid wall behind the rod, for repeated impacts (default "
     "none: the paper's single wall; >= 0)",
     "", ""},
    {"mass", G::scene, K::choice, "",
     "mass matrix (default lumped); redistributed and singular leave the rod's contact nodes "
     "massless (docs/remedies.md), taken by the methods `impactid methods` says step them",
     "lumped|consistent|redistributed|singular", ""},
    {"rayleigh_mass", G::scene, K::real, "1/s", "Rayleigh a0 in C = a0*M + a1*K (default 0)", "",
     ""},
    {"rayleigh_stiffness", G::scene, K::real, "s", "Rayleigh a1 in C = a0*M + a1*K (default 0)", "",
     ""},
    {"courant", G::scene, K::real, "", "Courant number c*dt/h (default 0.5, > 0); not with dt", "",
     ""},
    {"dt", G::scene, K::real, "s", "time step (default from courant); not with courant", "", ""},
    {"t_end", G::scene, K::real, "s", "end time (default t_impact + 1.5*2L/c)", "", ""},
};

constexpr ParameterInfo kOutputParameters[] = {
    {"peak_prominence", G::output, K::real, "",
     "minimum prominence of a counted peak, as a fraction of rho*c*v0 (pressure) and |v0| "
     "(velocity) (default 1e-6, > 0)",
     "", ""},
    {"reference_tolerance", G::output, K::real, "",
     "a scene of bodies with damping is measured against a numerical solution refined until "
     "its primary contact changes by less than this (default 1e-2, > 0; a model's: 1e-3)",
     "", ""},
    {"reference_method", G::output, K::choice, "",
     "method of a converged reference, at its default parameters (default auto: hht for a "
     "scene of bodies; for a model cdm when M is diagonal, else hht)",
     "" /* "auto|" and the method names: table() */, ""},
    {"reference_max_refinements", G::output, K::integer, "",
     "most halvings of a converged reference's step (default 5 for a scene of bodies, which "
     "also halves its mesh; 10 for a model), >= 1",
     "", ""},
    {"energy_growth_limit", G::output, K::real, "",
     "a run is unstable once its energy exceeds this multiple of the initial energy (default "
     "1.5, > 1)",
     "", ""},
    {"verdict_eps_p", G::output, K::real, "",
     "largest eps_p of an accurate run; above it the verdict is inaccurate (default 0.03, >= 0)",
     "", ""},
    {"verdict_nop_p", G::output, K::real, "",
     "most pressure peaks NoP_p of an accurate run; above them oscillating (default 15, >= 0)", "",
     ""},
    {"verdict_eps_v", G::output, K::real, "",
     "largest eps_v of an accurate run; above it the verdict is inaccurate (default 0.06, >= 0)",
     "", ""},
    {"verdict_nop_v", G::output, K::real, "",
     "most velocity peaks NoP_v of an accurate run; above them oscillating (default 15, >= 0)", "",
     ""},
};

// The table, built once: the contact law's and the method's rows and choice lists come from their
// registries, their text kept in `text` (a deque: its strings do not move).
struct ParameterTable {
  std::deque<std::string> text;
  std::vector<ParameterInfo> rows;
};

const ParameterTable& table() {
  static const ParameterTable t = [] {
    ParameterTable out;
    const auto keep = [&](std::string s) { return out.text.emplace_back(std::move(s)).c_str(); };
    for (const ParameterInfo& info : kSceneParameters) {
      out.rows.push_back(info);
      if (std::string_view(info.name) != "mass") continue;
      out.rows.push_back({"contact", G::scene, K::choice, "",
                          "how contacts are enforced (default lagrange; `impactid contact-laws` "
                          "lists each law with its parameters)",
                          keep(contact_law_names()), ""});
      for (const ContactLawParameter& p : contact_law_parameters()) {
        out.rows.push_back(
            {p.name, G::scene, p.integer ? K::integer : K::real, p.unit, p.description, "", ""});
      }
    }
    out.rows.push_back({"method", G::method, K::choice, "", "time-stepping method (default hht)",
                        keep(method_names()), ""});
    for (const MethodParameter& p : method_parameters()) {
      out.rows.push_back({p.name, G::method, p.choice ? K::choice : K::real, "", p.description,
                          p.choices, keep(methods_taking(p.name))});
    }
    for (ParameterInfo info : kOutputParameters) {
      if (std::string_view(info.name) == "reference_method") {
        info.choices = keep("auto|" + method_names());
      }
      out.rows.push_back(info);
    }
    return out;
  }();
  return t;
}

bool has_choice(const char* choices, std::string_view word) {
  const std::string_view list = choices;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find('|', start), list.size());
    if (list.substr(start, end - start) == word) return true;
    start = end + 1;
  }
  return false;
}

std::string choice_text(const ParameterValue& value) {
  if (const auto* text = std::get_if<std::string>(&value)) return *text;
  return format_value(std::get<double>(value));
}

std::optional<ParameterError> assign_choice(SimulationSettings& s, const ParameterInfo& info,
                                            const std::string& text) {
  const std::string name = info.name;
  const auto bad = [&] {
    return ParameterError{info.name, text, std::string("must be one of ") + info.choices};
  };
  if (name == "mass") {
    const auto v = mass_matrix_from_string(text);
    if (!v) return bad();
    s.scene.mass = *v;
  } else if (name == "contact") {
    const ContactLawDescriptor* law = find_contact_law(text);
    if (!law) return bad();
    s.run.contact.law = law->law;
  } else if (name == "method") {
    const auto v = method_kind_from_string(text);
    if (!v) return bad();
    s.method.kind = *v;
  } else if (find_method_parameter(name)) {
    if (!has_choice(info.choices, text)) return bad();
    s.method.given.set(name, text);
  } else if (name == "reference_method") {
    if (text == "auto") {
      s.reference.method.reset();
    } else {
      const auto v = method_kind_from_string(text);
      if (!v) return bad();
      s.reference.method = *v;
    }
  }
  return std::nullopt;
}

std::optional<ParameterError> assign_number(SimulationSettings& s, const ParameterInfo& info,
                                            double v) {
  const std::string name = info.name;
  if (info.kind == ParameterKind::integer) {
    if (!(std::isfinite(v) && v == std::floor(v) && std::abs(v) < 2e9)) {
      return ParameterError{info.name, format_value(v), "must be an integer below 2e9"};
    }
  }
  for (const char* key :
       {"length", "elements", "youngs_modulus", "density", "area", "velocity", "gap", "far_gap"}) {
    if (name == key) s.rod_keys.emplace_back(name, v);
  }
  if (name == "length")
    s.scene.length = v;
  else if (name == "elements")
    s.scene.elements = static_cast<int>(v);
  else if (name == "youngs_modulus")
    s.scene.youngs_modulus = v;
  else if (name == "density")
    s.scene.density = v;
  else if (name == "area")
    s.scene.area = v;
  else if (name == "velocity")
    s.scene.velocity = v;
  else if (name == "gap")
    s.scene.gap = v;
  else if (name == "far_gap")
    s.scene.far_gap = v;
  else if (name == "rayleigh_mass")
    s.scene.rayleigh_mass = v;
  else if (name == "rayleigh_stiffness")
    s.scene.rayleigh_stiffness = v;
  else if (name == "courant") {
    if (s.scene.dt) return ParameterError{"courant", format_value(v), "cannot be given with dt"};
    s.scene.courant = v;
    s.courant_given = true;
  } else if (name == "dt") {
    if (s.courant_given) {
      return ParameterError{"dt", format_value(v), "cannot be given with courant"};
    }
    s.scene.dt = v;
  } else if (name == "t_end")
    s.scene.t_end = v;
  else if (find_method_parameter(name))
    s.method.given.set(name, v);
  else if (name == "peak_prominence")
    s.indicators.peak_prominence = v;
  else if (name == "reference_tolerance") {
    s.indicators.reference_tolerance = v;
    s.reference_tolerance_given = true;
  } else if (name == "reference_max_refinements") {
    s.reference.max_refinements = static_cast<int>(v);
  } else if (name == "energy_growth_limit")
    s.run.energy_growth_limit = v;
  else if (name == "verdict_eps_p")
    s.verdict.eps_p = v;
  else if (name == "verdict_nop_p")
    s.verdict.nop_p = v;
  else if (name == "verdict_eps_v")
    s.verdict.eps_v = v;
  else if (name == "verdict_nop_v")
    s.verdict.nop_v = v;
  else if (const ContactLawParameter* p = find_contact_law_parameter(name))
    p->assign(s.run.contact, v);
  return std::nullopt;
}

}  // namespace

std::span<const ParameterInfo> parameter_table() {
  return table().rows;
}

const ParameterInfo* find_parameter(std::string_view name) {
  for (const auto& info : table().rows) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

std::optional<ParameterError> assign(SimulationSettings& settings, std::string_view name,
                                     const ParameterValue& value) {
  if (settings.model && name == "primary_contact") {
    const auto* text = std::get_if<std::string>(&value);
    if (!text) return ParameterError{"primary_contact", choice_text(value), "must be a string"};
    settings.model->primary_contact = *text;
    return std::nullopt;
  }
  if (is_scene_path(name)) {
    if (!settings.bodies) {
      return ParameterError{std::string(name), choice_text(value),
                            "is a key of a scene of bodies ([[scene.body]]); this scene is the "
                            "one-body rod (length, elements, velocity, gap, ...)"};
    }
    return assign_scene_path(*settings.bodies, name, value);
  }
  const ParameterInfo* info = find_parameter(name);
  if (!info) return ParameterError{std::string(name), choice_text(value), "is not a parameter"};
  if (info->kind == ParameterKind::choice) {
    const auto* text = std::get_if<std::string>(&value);
    if (!text) {
      return ParameterError{info->name, choice_text(value),
                            std::string("must be one of ") + info->choices};
    }
    return assign_choice(settings, *info, *text);
  }
  const auto* number = std::get_if<double>(&value);
  if (!number) {
    return ParameterError{info->name, '"' + std::get<std::string>(value) + '"', "must be a number"};
  }
  return assign_number(settings, *info, *number);
}

std::optional<ParameterError> assign_text(SimulationSettings& settings, std::string_view name,
                                          std::string_view text) {
  if (name == "primary_contact") return assign(settings, name, std::string(text));
  if (!is_scene_path(name)) {  // a scene of bodies' other keys are numbers
    const ParameterInfo* info = find_parameter(name);
    if (!info) return ParameterError{std::string(name), std::string(text), "is not a parameter"};
    if (info->kind == ParameterKind::choice) return assign(settings, name, std::string(text));
  }
  double v = 0.0;
  const std::string t(text);
  // from_chars accepts "nan" and "inf": they are then rejected by the range checks, by name.
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range && end == t.data() + t.size()) {
    return ParameterError{std::string(name), t,
                          "is a number beyond the range of double (magnitudes from about "
                          "2.2e-308 to 1.8e308)"};
  }
  if (ec != std::errc() || end != t.data() + t.size() || t.empty()) {
    return ParameterError{std::string(name), t, "must be a number"};
  }
  return assign(settings, name, v);
}

std::variant<Simulation, ParameterError> build(const SimulationSettings& s) {
  auto method = build_method(s.method.kind, s.method.given);
  if (const auto* e = std::get_if<ParameterError>(&method)) return *e;
  Simulation out{s.scene, std::get<MethodParams>(method), s.indicators, s.run, s.reference};
  out.verdict = s.verdict;
  if (s.model) {
    if (!s.rod_keys.empty()) {
      return ParameterError{s.rod_keys.front().first, format_value(s.rod_keys.front().second),
                            "is a key of the one-body rod: a model (kind = \"matrices\") has its "
                            "matrices, initial state and contacts instead"};
    }
    // The rod's lumped or consistent mass: a model's M is its file, so anything but the default
    // would be silently ignored.
    if (s.scene.mass != MassMatrix::lumped) {
      return ParameterError{"mass", to_string(s.scene.mass),
                            "is a key of the one-body rod: a model's mass matrix is its file "
                            "([scene.matrices] mass; lump it there)"};
    }
    ModelScene scene = *s.model;
    if (s.courant_given) {
      // A model's Courant number is Δt·ω/2, ω the Gershgorin bound of its highest frequency
      // (core/model/model_scene.hpp: gershgorin_omega).
      if (!(s.scene.courant > 0.0 && std::isfinite(s.scene.courant))) {
        return ParameterError{"courant", format_value(s.scene.courant),
                              "must be positive and finite"};
      }
      scene.dt = 2.0 * s.scene.courant / scene.model->omega_bound;
    } else if (!s.scene.dt) {
      return ParameterError{"dt", "(missing)", "a model needs its time step dt (or courant)"};
    } else {
      scene.dt = *s.scene.dt;
    }
    if (!s.scene.t_end) {
      return ParameterError{"t_end", "(missing)", "a model needs its end time t_end"};
    }
    scene.t_end = *s.scene.t_end;
    scene.rayleigh_mass = s.scene.rayleigh_mass;
    scene.rayleigh_stiffness = s.scene.rayleigh_stiffness;
    if (auto e = validate(scene)) return *e;
    // A model's converged reference has its own default tolerance
    // (core/reference/model_reference.hpp).
    if (!s.reference_tolerance_given) {
      out.indicators.reference_tolerance = model_reference_defaults(*scene.model).tolerance;
    }
    out.scene = std::move(scene);
  } else if (s.bodies) {
    if (!s.rod_keys.empty()) {
      return ParameterError{s.rod_keys.front().first, format_value(s.rod_keys.front().second),
                            "is a key of the one-body rod: a scene of bodies gives it on a body "
                            "or a segment (body.<name>.velocity, body.<name>.segment.<k>.length, "
                            "wall.right.gap, ...)"};
    }
    Scene scene = *s.bodies;
    scene.mass = s.scene.mass;
    scene.rayleigh_mass = s.scene.rayleigh_mass;
    scene.rayleigh_stiffness = s.scene.rayleigh_stiffness;
    scene.courant = s.scene.courant;
    scene.dt = s.scene.dt;
    scene.t_end = s.scene.t_end;
    if (auto e = validate(scene)) return *e;
    out.scene = std::move(scene);
  } else if (auto e = validate(s.scene)) {
    return *e;
  }
  if (auto e = validate(out.method)) return *e;
  if (has_massless_dofs(s.scene.mass)) {
    // Whether the method steps a contact DOF without mass is its descriptor's to say.
    if (auto refusal = massless_refusal(descriptor(out.method), s.scene.rayleigh_stiffness)) {
      return ParameterError{"mass", to_string(s.scene.mass), *refusal};
    }
  }
  if (!(out.indicators.peak_prominence > 0.0 && std::isfinite(out.indicators.peak_prominence))) {
    return ParameterError{"peak_prominence", format_value(out.indicators.peak_prominence),
                          "must be positive and finite"};
  }
  if (!(out.indicators.reference_tolerance > 0.0 &&
        std::isfinite(out.indicators.reference_tolerance))) {
    return ParameterError{"reference_tolerance", format_value(out.indicators.reference_tolerance),
                          "must be positive and finite"};
  }
  if (s.reference.max_refinements && !(*s.reference.max_refinements >= 1)) {
    return ParameterError{"reference_max_refinements", std::to_string(*s.reference.max_refinements),
                          "must be >= 1"};
  }
  if (auto e = validate(out.run.contact)) return *e;
  // Whether the method takes the contact law is its descriptor's to say.
  if (auto refusal = contact_law_refusal(descriptor(out.method), out.run.contact.law)) {
    return ParameterError{"contact", to_string(out.run.contact.law), *refusal};
  }
  if (!(out.run.energy_growth_limit > 1.0)) {
    return ParameterError{"energy_growth_limit", format_value(out.run.energy_growth_limit),
                          "must be > 1"};
  }
  if (auto e = validate(out.verdict)) return *e;
  return out;
}

std::optional<double> numeric_value(const Simulation& sim, std::string_view name) {
  // NaN: penalty_stiffness not given (the factor applies).
  if (const ContactLawParameter* p = find_contact_law_parameter(name))
    return p->value(sim.run.contact);
  if (name == "verdict_eps_p") return sim.verdict.eps_p;
  if (name == "verdict_nop_p") return sim.verdict.nop_p;
  if (name == "verdict_eps_v") return sim.verdict.eps_v;
  if (name == "verdict_nop_v") return sim.verdict.nop_v;
  if (const ModelScene* model = sim.model()) {
    if (name == "dt") return model->dt;
    if (name == "courant") return model->dt * model->model->omega_bound / 2.0;
    if (name == "t_end") return model->t_end;
    if (name == "rayleigh_mass") return model->rayleigh_mass;
    if (name == "rayleigh_stiffness") return model->rayleigh_stiffness;
    if (name == "reference_tolerance") return sim.indicators.reference_tolerance;
    if (name == "reference_max_refinements") return reference_options(sim).max_refinements;
    const ParameterInfo* info = find_parameter(name);
    if (info && info->group == ParameterGroup::scene) return std::nullopt;  // the rod's keys
  } else if (const Scene* bodies = sim.bodies()) {
    const SceneDerived d = derive(*bodies);
    if (is_scene_path(name)) return scene_path_value(*bodies, name);
    if (name == "courant") return d.time_step / d.min_h_over_c;
    if (name == "dt") return d.time_step;
    if (name == "t_end") return d.end_time;
    if (name == "rayleigh_mass") return bodies->rayleigh_mass;
    if (name == "rayleigh_stiffness") return bodies->rayleigh_stiffness;
    if (name == "reference_tolerance") return sim.indicators.reference_tolerance;
    if (name == "reference_max_refinements") return reference_options(sim).max_refinements;
    for (const char* key : {"length", "elements", "youngs_modulus", "density", "area", "velocity",
                            "gap", "far_gap"}) {
      if (name == key) return std::nullopt;  // the rod's keys: not this scene's
    }
  } else {
    const RodScene& sc = std::get<RodScene>(sim.scene);
    const RodSceneDerived d = derive(sc);
    if (name == "length") return sc.length;
    if (name == "elements") return sc.elements;
    if (name == "youngs_modulus") return sc.youngs_modulus;
    if (name == "density") return sc.density;
    if (name == "area") return sc.area;
    if (name == "velocity") return sc.velocity;
    if (name == "gap") return sc.gap;
    if (name == "far_gap") return sc.far_gap;
    if (name == "rayleigh_mass") return sc.rayleigh_mass;
    if (name == "rayleigh_stiffness") return sc.rayleigh_stiffness;
    if (name == "courant") return d.time_step * d.wave_speed / d.element_length;
    if (name == "dt") return d.time_step;
    if (name == "t_end") return d.end_time;
    // The rod's reference is exact.
    if (name == "reference_tolerance" || name == "reference_max_refinements") return std::nullopt;
  }
  if (name == "peak_prominence") return sim.indicators.peak_prominence;
  if (name == "energy_growth_limit") return sim.run.energy_growth_limit;
  if (find_method_parameter(name)) return reported_value(sim.method, name);
  return std::nullopt;
}

MassMatrix mass_key(const Simulation& sim) {
  return std::visit(Overloaded{[](const RodScene& rod) { return rod.mass; },
                               [](const Scene& bodies) { return bodies.mass; },
                               [](const ModelScene&) { return MassMatrix::lumped; }},
                    sim.scene);
}

std::string method_values_text(const MethodParams& method) {
  std::string out;
  for (const ReportedValue& v : descriptor(method).values(method)) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%s%s = %.6g", out.empty() ? " (" : ", ", v.name, v.value);
    out += buffer;
  }
  return out.empty() ? out : out + ")";
}

ReferenceOptions reference_options(const Simulation& sim) {
  ReferenceOptions options =
      sim.model() ? model_reference_defaults(*sim.model()->model) : ReferenceOptions{};
  options.tolerance = sim.indicators.reference_tolerance;
  if (sim.reference.method) options.method = default_params(*sim.reference.method);
  if (sim.reference.max_refinements) options.max_refinements = *sim.reference.max_refinements;
  return options;
}

}  // namespace impactid
