#include "study/cli/spectral_command.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "core/spectral/amplification.hpp"
#include "study/cli/command_line.hpp"
#include "study/formats/json_writer.hpp"
#include "study/studies/damping_match.hpp"
#include "study/studies/spectral_report.hpp"
#include "study/studies/spectral_study.hpp"

namespace impactid {
namespace {

const char* const kCommand = "spectral";

struct Options {
  GivenOptions given;  // method options, and --courant/--mass for Ω_max
  std::vector<std::string> omega_dt;
  std::string omega_max;
  std::string match_damping;
  bool json = false;
};

void bad_input(const std::string& option, const std::string& value, const std::string& what) {
  std::cerr << "impactid " << kCommand << ": " << option << " = " << value << ": " << what << '\n';
}

// Strict: the whole text is one number ("1e-3"; not "1x", not ""). NaN and infinities parse and
// are rejected by the caller's range check, by name.
std::optional<double> parse_number(const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

std::optional<double> positive_number(const std::string& option, const std::string& text) {
  const auto v = parse_number(text);
  if (!v) {
    bad_input(option, text, "must be a number");
    return std::nullopt;
  }
  if (!(*v > 0.0 && std::isfinite(*v))) {
    bad_input(option, text, "must be positive and finite");
    return std::nullopt;
  }
  return v;
}

bool is_method_option(const std::string& name) {
  const ParameterInfo* info = find_parameter(name);
  return info && info->group == ParameterGroup::method;
}

// ---- one method ---------------------------------------------------------------------------

void write_method_json(const SpectralReport& r) {
  JsonWriter json(std::cout);
  json.begin_object();
  json.key("method").value(to_string(kind_of(r.simulation.method)));
  json.key("parameters").begin_object();
  for (const ParameterInfo& info : parameter_table()) {
    if (info.group != ParameterGroup::method || info.kind == ParameterKind::choice) continue;
    if (const auto v = numeric_value(r.simulation, info.name)) json.key(info.name).value(*v);
  }
  json.end_object();
  json.key("rho_inf").value(r.rho_inf);
  json.key("period_error_coefficient").value(r.period_error_coefficient);
  json.key("stability").begin_object();
  json.key("omega_min").value(std::min(kStabilityScanMinOmega, r.omega_max));
  json.key("omega_max").value(r.omega_max);
  json.key("omega_max_from").value(r.omega_max_from);
  json.key("max_spectral_radius").value(r.max_rho);
  json.key("stable").value(r.stable);
  json.end_object();
  if (r.alpha) {
    json.key("delta_min_period_error").begin_object();
    json.key("limit").value(r.delta_min_limit);
    json.key("eq19").value(-1.5 * *r.alpha);
    json.end_object();
  }
  json.key("omega_dt").begin_array();
  for (const SpectralAtOmega& a : r.at) {
    json.begin_object();
    json.key("omega_dt").value(a.omega_dt);
    json.key("spectral_radius").value(a.properties.spectral_radius);
    json.key("damping_ratio").value(a.properties.damping_ratio);
    json.key("period_error").value(a.properties.period_error);
    json.key("oscillatory").value(a.properties.oscillatory);
    if (r.alpha) json.key("delta_min_period_error").value(a.delta_min);
    json.end_object();
  }
  json.end_array();
  json.end_object();
  std::cout << '\n';
}

void write_method_text(const SpectralReport& r) {
  std::printf("method      %s%s\n", to_string(kind_of(r.simulation.method)),
              method_values_text(r.simulation.method).c_str());
  std::printf("rho_inf     %.6g (spectral radius as omega*dt -> inf)\n", r.rho_inf);
  std::printf("period      (T_num - T)/T = c*(omega*dt)^2 as omega*dt -> 0, c = %.6g\n",
              r.period_error_coefficient);
  std::printf("stability   max rho = %.10g over omega*dt in [%g, %g] (%s): %s\n", r.max_rho,
              std::min(kStabilityScanMinOmega, r.omega_max), r.omega_max, r.omega_max_from,
              r.stable ? "stable" : "UNSTABLE");
  if (r.alpha) {
    std::printf(
        "delta_min   %.6g minimises the period error as omega*dt -> 0 (eq. 19: "
        "-1.5*alpha = %.6g)\n",
        r.delta_min_limit, -1.5 * *r.alpha);
  }
  if (r.at.empty()) return;
  std::printf("%-12s %-14s %-14s %-14s%s\n", "omega*dt", "rho", "xi", "period_error",
              r.alpha ? " delta_min" : "");
  for (const SpectralAtOmega& a : r.at) {
    std::printf("%-12.6g %-14.8g %-14.8g %-14.8g", a.omega_dt, a.properties.spectral_radius,
                a.properties.damping_ratio, a.properties.period_error);
    if (r.alpha) std::printf(" %.6g", a.delta_min);
    std::printf("\n");
  }
}

int run_method(const Options& o, const std::vector<double>& omegas) {
  SimulationSettings settings;
  if (!apply_options(o.given, settings, kCommand)) return kExitBadInput;
  const auto simulation = build_or_report(settings, kCommand);
  if (!simulation) return kExitBadInput;

  std::optional<double> omega_max;
  const bool scene_given = o.given.count("courant") || o.given.count("mass");
  if (!o.omega_max.empty()) {
    if (scene_given) {
      bad_input("--omega-max", o.omega_max, "cannot be given with --courant or --mass");
      return kExitBadInput;
    }
    omega_max = positive_number("--omega-max", o.omega_max);
    if (!omega_max) return kExitBadInput;
  }
  const SpectralReport r = spectral_report(*simulation, omega_max, scene_given, omegas);
  if (o.json) {
    write_method_json(r);
  } else {
    write_method_text(r);
  }
  return 0;
}

// ---- --match-damping ----------------------------------------------------------------------

int run_match(const Options& o, double omega_dt, double target) {
  std::vector<DampingMatch> matches;
  for (const DampingFamilyInfo& f : damping_families()) {
    matches.push_back(match_damping(f.family, omega_dt, target));
  }
  const auto fixed = fixed_damping_methods();
  if (o.json) {
    JsonWriter json(std::cout);
    json.begin_object();
    json.key("omega_dt").value(omega_dt);
    json.key("damping_ratio").value(target);
    json.key("matches").begin_array();
    for (const DampingMatch& m : matches) {
      const DampingFamilyInfo& f = family_info(m.family);
      json.begin_object();
      json.key("family").value(f.name);
      json.key("method").value(family_method(m.family));
      json.key("parameter").value(f.parameter);
      json.key("reachable").value(m.reachable);
      json.key("value").value(m.parameter);
      json.key("damping_ratio").value(m.damping_ratio);
      json.key("parameters");
      if (m.reachable) {
        json.begin_object();
        for (const auto& [name, v] : family_parameters(m.family, m.parameter))
          json.key(name).value(v);
        json.end_object();
      } else {
        json.null();
      }
      json.key("range").begin_array().value(f.undamped_end).value(f.damped_end).end_array();
      json.key("attainable")
          .begin_array()
          .value(m.attainable_min)
          .value(m.attainable_max)
          .end_array();
      json.key("roots").value(m.roots);
      json.end_object();
    }
    json.end_array();
    json.key("fixed").begin_array();
    for (const auto& [name, params] : fixed) {
      json.begin_object();
      json.key("method").value(name);
      json.key("damping_ratio").value(spectral_properties(params, omega_dt).damping_ratio + 0.0);
      json.end_object();
    }
    json.end_array();
    json.end_object();
    std::cout << '\n';
    return 0;
  }
  std::printf("target      xi = %s at omega*dt = %s\n", format_value(target).c_str(),
              format_value(omega_dt).c_str());
  std::printf("%-26s %-9s %-22s %s\n", "method", "parameter", "value", "xi(omega*dt)");
  for (const DampingMatch& m : matches) {
    const DampingFamilyInfo& f = family_info(m.family);
    if (m.reachable) {
      std::printf("%-26s %-9s %-22s %s%s\n", f.label, f.parameter,
                  format_value(m.parameter).c_str(), format_value(m.damping_ratio).c_str(),
                  m.roots > 1 ? "  (several roots; the least dissipative parameter)" : "");
    } else {
      std::printf("%-26s %-9s not reachable: xi(omega*dt) in [%.6g, %.6g] for %s in [%g, %g]\n",
                  f.label, f.parameter, m.attainable_min, m.attainable_max, f.parameter,
                  std::min(f.undamped_end, f.damped_end), std::max(f.undamped_end, f.damped_end));
    }
  }
  for (const auto& [name, params] : fixed) {
    // + 0.0 prints central difference's -0 as 0
    std::printf("%-26s %-9s %-22s %s\n", name, "-", "(fixed)",
                format_value(spectral_properties(params, omega_dt).damping_ratio + 0.0).c_str());
  }
  return 0;
}

}  // namespace

std::function<int()> add_spectral_command(CLI::App& app) {
  auto* command = app.add_subcommand(
      "spectral",
      "Spectral analysis of a method on the undamped oscillator: rho_inf, period error, "
      "stability, and rho, xi, period error at given omega*dt; or --match-damping");
  auto o = std::make_shared<Options>();
  add_parameter_options(*command, o->given, {ParameterGroup::method});
  for (const char* name : {"courant", "mass"}) {
    const ParameterInfo* info = find_parameter(name);
    const std::string key = name;
    command
        ->add_option_function<std::string>(
            option_name(key), [o, key](const std::string& v) { o->given[key] = v; },
            std::string(info->description) +
                "; sets the stability scan's omega_max to the rod's highest mode, "
                "2*courant (lumped) or 2*sqrt(3)*courant (consistent)")
        ->type_name(*info->choices ? info->choices : "NUMBER");
  }
  command
      ->add_option("--omega-dt", o->omega_dt,
                   "omega*dt at which to report rho, xi and the period error; repeatable, or "
                   "a comma-separated list")
      ->delimiter(',')
      ->type_name("W");
  command
      ->add_option("--omega-max", o->omega_max,
                   "upper end of the stability scan (default 1e4, or the rod's highest mode "
                   "with --courant/--mass)")
      ->type_name("W");
  command
      ->add_option("--match-damping", o->match_damping,
                   "find, for newmark (delta), hht with delta = -1.5*alpha (alpha), hht with "
                   "delta = -alpha (alpha) and generalized-alpha (rho_inf), the parameter "
                   "whose algorithmic damping ratio at the one --omega-dt is XI")
      ->type_name("XI");
  command->add_flag("--json", o->json, "Print one JSON object instead of text");

  return [command, o]() -> int {
    if (!command->parsed()) return -1;
    std::vector<double> omegas;
    for (const std::string& text : o->omega_dt) {
      const auto v = positive_number("--omega-dt", text);
      if (!v) return kExitBadInput;
      omegas.push_back(*v);
    }
    if (o->match_damping.empty()) return run_method(*o, omegas);

    if (!o->given.empty()) {
      const auto& [name, value] = *o->given.begin();
      bad_input(option_name(name), value,
                is_method_option(name)
                    ? "not used with --match-damping (it matches every method family)"
                    : "not used with --match-damping (it needs no stability scan)");
      return kExitBadInput;
    }
    if (!o->omega_max.empty()) {
      bad_input("--omega-max", o->omega_max, "not used with --match-damping");
      return kExitBadInput;
    }
    const auto target = parse_number(o->match_damping);
    if (!target) {
      bad_input("--match-damping", o->match_damping, "must be a number");
      return kExitBadInput;
    }
    if (!(*target >= 0.0 && std::isfinite(*target))) {
      bad_input("--match-damping", o->match_damping, "must be >= 0 and finite");
      return kExitBadInput;
    }
    if (omegas.size() != 1) {
      bad_input("--omega-dt",
                omegas.empty() ? "(missing)" : std::to_string(omegas.size()) + " values",
                "--match-damping needs exactly one --omega-dt");
      return kExitBadInput;
    }
    return run_match(*o, omegas.front(), *target);
  };
}

}  // namespace impactid
