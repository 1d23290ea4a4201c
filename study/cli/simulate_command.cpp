#include "study/cli/simulate_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "core/contact/contact_law_registry.hpp"
#include "study/cli/command_line.hpp"
#include "study/formats/json_writer.hpp"
#include "study/io/history_file.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

// Every numeric parameter the run used (derived δ, β, γ included), in table order.
template <class Emit>
void for_each_used_parameter(const Simulation& sim, Emit&& emit) {
  for (const ParameterInfo& info : parameter_table()) {
    if (info.kind == ParameterKind::choice) continue;
    if (const auto value = numeric_value(sim, info.name)) emit(info.name, *value);
  }
}

// The contact law's line of the text report, for a law with springs, and a run's warning.
void write_contact_law(const Simulation& sim, const Evaluation& e) {
  const ContactTreatment& c = sim.run.contact;
  const ContactLawDescriptor& law = descriptor(c.law);
  if (law.springs) {
    std::string stiffness = c.penalty_stiffness
                                ? "k = " + format_value(*c.penalty_stiffness) + " N/mm"
                                : "k = " + format_value(c.penalty_factor) + " x K_cc";
    std::printf("contact law %s, %s; largest penetration = %.4g mm", to_string(c.law),
                stiffness.c_str(), e.indicators.max_penetration);
    if (law.iterates) {
      std::printf("; %ld iteration(s), %ld step(s) at the cap of %d", e.summary.contact_iterations,
                  e.summary.unconverged_contact_steps, c.augmented_max_iterations);
    }
    std::printf("\n");
  }
  if (std::isfinite(e.summary.stable_dt) && law.explicit_force) {
    std::printf("stable dt   %.6g s (central difference with the penalty springs)\n",
                e.summary.stable_dt);
  } else if (const MethodDescriptor& m = descriptor(sim.method); m.stable_step) {
    if (e.summary.stable_dt > 0.0) {
      std::printf("stable dt   %.6g s (%s: %s)\n", e.summary.stable_dt, m.name, m.stable_step);
    } else {
      std::printf("stable dt   not certified (%s: it needs a diagonal mass)\n", m.name);
    }
  }
  if (!e.summary.warning.empty()) std::printf("warning     %s\n", e.summary.warning.c_str());
}

void write_json(const Simulation& sim, const Evaluation& e,
                const std::vector<EpisodeComparison>& episodes) {
  const RodScene* rod = sim.rod();
  const Scene* bodies = sim.bodies();
  const ModelScene* model = sim.model();
  JsonWriter json(std::cout);
  json.begin_object();
  json.key("method").value(to_string(kind_of(sim.method)));
  json.key("parameters").begin_object();
  for_each_used_parameter(sim, [&](const char* name, double v) { json.key(name).value(v); });
  json.key("mass").value(to_string(mass_key(sim)));
  const MethodDescriptor& method = descriptor(sim.method);
  for (const auto& [name, word] : method.choices(sim.method)) json.key(name).value(word);
  // Derived coefficients that are no parameter of any method (generalized-alpha's alpha_m and
  // alpha_f); beta and gamma are among the parameters above.
  for (const ReportedValue& v : method.values(sim.method)) {
    if (!find_parameter(v.name)) json.key(v.name).value(v.value);
  }
  json.end_object();
  json.key("dt").value(e.summary.dt);
  json.key("steps").value(e.summary.steps);
  json.key("planned_steps").value(e.summary.planned_steps);
  json.key("status").value(to_string(e.summary.status));
  json.key("verdict").value(to_string(e.verdict));
  json.key("verdict_reason")
      .value(verdict_reason(e.summary.status, e.indicators, e.reference_trusted, sim.verdict));
  json.key("message").value(e.summary.message);
  json.key("warning").value(e.summary.warning);
  json.key("contact").value(to_string(sim.run.contact.law));
  if (descriptor(sim.run.contact.law).springs) {
    json.key("contact_iterations").value(e.summary.contact_iterations);
    json.key("unconverged_contact_steps").value(e.summary.unconverged_contact_steps);
    json.key("stable_dt").value(e.summary.stable_dt);
    if (rod && !rod->far_gap) {
      json.key("max_penetration").value(e.indicators.max_penetration);
    }
  }
  json.key("eps_p").value(e.indicators.eps_p);
  json.key("eps_v").value(e.indicators.eps_v);
  json.key("nop_p").value(e.indicators.nop_p);
  json.key("nop_v").value(e.indicators.nop_v);
  json.key("p_max").value(e.indicators.p_max);
  json.key("p_max_ratio").value(e.indicators.p_max_ratio);
  if (rod) json.key("pressure_scale").value(derive(*rod).pressure_scale);
  json.key("contact_episodes").value(e.indicators.contact_episodes);
  json.key("energy_ratio").value(e.indicators.energy_ratio);
  if (rod && rod->far_gap) {
    json.key("far_contact_episodes").value(e.indicators.far_contact_episodes);
    json.key("impacts").value(e.indicators.impacts);
    json.key("max_penetration").value(e.indicators.max_penetration);
  }
  if (!rod) {
    json.key("max_penetration").value(e.indicators.max_penetration);
    std::vector<std::string> contacts;
    int primary = 0;
    if (bodies) {
      for (const SceneContact& c : scene_contacts(*bodies)) contacts.push_back(c.name);
      primary = derive(*bodies).primary_contact;
    } else {
      for (const ModelContact& c : model->model->contacts) contacts.push_back(c.name);
      primary = primary_contact_index(*model);
      json.key("reference").value(e.reference);
    }
    json.key("reference_trusted").value(e.reference_trusted);
    json.key("reference_error").value(e.reference_error);
    json.key("primary_contact").value(contacts[static_cast<std::size_t>(primary)]);
    json.key("contacts").begin_array();
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      const ContactIndicators& c = e.contacts[k];
      json.begin_object();
      json.key("name").value(contacts[k]);
      json.key("eps_p").value(c.eps_p);
      json.key("eps_v").value(c.eps_v);
      json.key("nop_p").value(c.nop_p);
      json.key("nop_v").value(c.nop_v);
      json.key("p_max").value(c.p_max);
      json.key("p_max_ratio").value(c.p_max_ratio);
      json.key("contact_episodes").value(c.contact_episodes);
      json.end_object();
    }
    json.end_array();
  }
  json.key("episodes").begin_array();
  for (const EpisodeComparison& c : episodes) {
    json.begin_object();
    json.key("start").value(c.start);
    json.key("reference_start").value(c.reference_start);
    json.key("end").value(c.end);
    json.key("reference_end").value(c.reference_end);
    json.key("impulse").value(c.impulse);
    json.key("reference_impulse").value(c.reference_impulse);
    json.key("peaks").value(c.peaks);
    json.key("contact_runs").value(c.contact_runs);
    json.key("energy_ratio").value(c.energy_ratio);
    json.end_object();
  }
  json.end_array();
  json.key("wall_time_s").value(e.summary.wall_time_s);
  json.end_object();
  std::cout << '\n';
}

// The primary contact's episodes beside the reference's (metrics/episodes.hpp), then the wall
// time: the last lines of a finished run's report. A long run lists its first and last ten.
void write_tail(const Evaluation& e, const std::vector<EpisodeComparison>& episodes) {
  if (!episodes.empty()) {
    std::printf(
        "episodes    %zu in the reference, the run's beside the reference's (in brackets): "
        "start and end [s], impulse sum p*dt\n",
        episodes.size());
    std::printf("               #  %23s  %23s  %23s  %5s  %4s  %s\n", "start", "end", "impulse",
                "peaks", "runs", "E/E0 after");
    for (std::size_t k = 0; k < episodes.size(); ++k) {
      if (episodes.size() > 20 && k == 10) {
        std::printf("            ... %zu more ...\n", episodes.size() - 20);
        k = episodes.size() - 10;
      }
      const EpisodeComparison& c = episodes[k];
      std::printf("            %4zu  %10.4g (%10.4g)  %10.4g (%10.4g)  %10.4g (%10.4g)  %5ld  %4ld",
                  k + 1, c.start, c.reference_start, c.end, c.reference_end, c.impulse,
                  c.reference_impulse, c.peaks, c.contact_runs);
      if (std::isnan(c.energy_ratio)) {
        std::printf("  %s\n", "-");
      } else {
        std::printf("  %.6g\n", c.energy_ratio);
      }
    }
    if (std::isnan(episodes.front().energy_ratio)) {
      std::printf("            (E/E0 after each episode: with --history, which records the energy)\n");
    }
  }
  std::printf("wall time   %.3g ms\n", e.summary.wall_time_s * 1e3);
}

// A scene of bodies: one line per body and wall, and the time grid.
// A wall's line: its gap, or that it clamps its end node.
void write_wall(const char* lead, const char* side, const Wall& wall) {
  if (wall.kind == WallKind::clamped) {
    std::printf("%s wall (%s), clamped: u = 0\n", lead, side);
  } else {
    std::printf("%s wall (%s), gap %g mm\n", lead, side, wall.gap);
  }
}

void write_bodies(const Scene& scene) {
  if (scene.left_wall) write_wall("scene      ", "left", *scene.left_wall);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    std::printf("%s body %-10s v0 = %g mm/s",
                b == 0 && !scene.left_wall ? "scene      " : "           ", body.name.c_str(),
                body.velocity);
    if (b > 0) std::printf(", gap %g mm", body.gap);
    if (!body.displacement.is_zero()) {
      std::printf(", u0 = [%g, %g] mm", body.displacement.left, body.displacement.right);
    }
    std::printf(":");
    for (const Segment& s : body.segments) {
      std::printf(" [L %g, n %d, E %g, rho %g, A %g]", s.length, s.elements, s.youngs_modulus,
                  s.density, s.area);
    }
    std::printf("\n");
  }
  if (scene.right_wall) write_wall("           ", "right", *scene.right_wall);
  if (scene.gravity != 0.0) {
    std::printf("            gravity g = %g mm/s^2, toward the %s wall\n", scene.gravity,
                scene.gravity < 0.0 ? "left" : "right");
  }
  const SceneDerived d = derive(scene);
  std::printf(
      "time        dt = %.6g s (Courant %.4g of the smallest h/c), %ld steps to t_end = "
      "%.6g s; %s mass\n",
      d.time_step, d.time_step / d.min_h_over_c, d.step_count, d.end_time, to_string(scene.mass));
}

// Every contact's indicators, the primary one marked. A model's pressure is in its own units
// and its scale is its reference's largest pressure (metrics/indicators.hpp).
void write_contacts(const std::vector<std::string>& names, int primary, bool model,
                    const Evaluation& e) {
  std::printf("contact       %-24s %10s %6s %10s %6s %11s %8s %8s\n", "", "eps_p", "NoP_p", "eps_v",
              "NoP_v", model ? "p_max" : "p_max[MPa]", model ? "p/p_ref" : "p/(rcV)", "episodes");
  for (std::size_t k = 0; k < names.size(); ++k) {
    const ContactIndicators& c = e.contacts[k];
    std::printf("            %s %-24s %10.4g %6g %10.4g %6g %11.4g %8.4g %8g\n",
                static_cast<int>(k) == primary ? "*" : " ", names[k].c_str(), c.eps_p, c.nop_p,
                c.eps_v, c.nop_v, c.p_max, c.p_max_ratio, c.contact_episodes);
  }
  std::printf("            (* the primary contact, whose indicators a sweep stores)\n");
}

void write_text(const Simulation& sim, const Evaluation& e,
                const std::vector<EpisodeComparison>& episodes) {
  std::printf("method      %s%s\n", to_string(kind_of(sim.method)),
              method_values_text(sim.method).c_str());
  std::visit(
      Overloaded{
          [](const RodScene& rod) {
            const RodSceneDerived d = derive(rod);
            std::printf(
                "scene       L = %g mm, n = %d, E = %g MPa, rho = %g t/mm^3, A = %g mm^2, "
                "v0 = %g mm/s, gap = %g mm, %s mass\n",
                rod.length, rod.elements, rod.youngs_modulus, rod.density, rod.area,
                rod.velocity, rod.gap, to_string(rod.mass));
            std::printf("time        dt = %.6g s (Courant %.4g), %ld steps to t_end = %.6g s\n",
                        d.time_step, d.time_step * d.wave_speed / d.element_length, d.step_count,
                        d.end_time);
          },
          [](const Scene& bodies) { write_bodies(bodies); },
          [](const ModelScene& scene) {
            const Model& model = *scene.model;
            std::printf("scene       model of %ld DOFs (%s), %zu contact(s)%s%s\n",
                        static_cast<long>(model.size()), model.source.c_str(),
                        model.contacts.size(), model.units.empty() ? "" : "; units ",
                        model.units.c_str());
            std::printf("time        dt = %.6g, %ld steps to t_end = %.6g\n", scene.dt,
                        step_count(scene.t_end, scene.dt), scene.t_end);
          }},
      sim.scene);
  std::printf("status      %s%s%s\n", to_string(e.summary.status),
              e.summary.message.empty() ? "" : ": ", e.summary.message.c_str());
  std::printf(
      "verdict     %s (%s)\n", to_string(e.verdict),
      verdict_reason(e.summary.status, e.indicators, e.reference_trusted, sim.verdict).c_str());
  write_contact_law(sim, e);
  if (e.summary.status != RunStatus::ok) {
    // The indicators of a run that did not finish are not results (NaN in JSON and in files).
    std::printf("indicators  none: the run is %s after %ld of %ld steps\n",
                to_string(e.summary.status), e.summary.steps, e.summary.planned_steps);
    std::printf("wall time   %.3g ms\n", e.summary.wall_time_s * 1e3);
    return;
  }
  if (const ModelScene* model = sim.model()) {
    std::vector<std::string> names;
    for (const ModelContact& c : model->model->contacts) names.push_back(c.name);
    write_contacts(names, primary_contact_index(*model), true, e);
    std::printf("reference   %s\n", e.reference.c_str());
    std::printf("            estimated error %.3g: an eps below it is not resolved\n",
                e.reference_error);
    // The penetration is tracked with a list of constraints and with a law that allows one
    // (penalty, augmented Lagrangian): a single Lagrange contact holds its constraint at every
    // sample, and its step loop is kept free of the bookkeeping (RunSummary::max_penetration).
    if (std::isfinite(e.indicators.max_penetration)) {
      std::printf("energy      at t_end / initial = %.6g; largest penetration = %.3g\n",
                  e.indicators.energy_ratio, e.indicators.max_penetration);
    } else {
      std::printf(
          "energy      at t_end / initial = %.6g; penetration not tracked (a single Lagrange "
          "contact holds its constraint at every sample)\n",
          e.indicators.energy_ratio);
    }
    write_tail(e, episodes);
    return;
  }
  if (const Scene* bodies = sim.bodies()) {
    std::vector<std::string> names;
    for (const SceneContact& c : scene_contacts(*bodies)) names.push_back(c.name);
    write_contacts(names, derive(*bodies).primary_contact, false, e);
    if (e.reference_refinements == 0) {
      std::printf("reference   the %s\n", e.reference.c_str());
    } else {
      const long factor = 1L << static_cast<int>(e.reference_refinements);
      std::printf(
          "reference   a converged numerical solution at h/%ld and dt/%ld (relative "
          "change %.3g at the last halving)\n",
          factor, factor, e.reference_change);
    }
    std::printf("energy      at t_end / initial = %.6g; largest penetration = %.3g mm\n",
                e.indicators.energy_ratio, e.indicators.max_penetration);
    write_tail(e, episodes);
    return;
  }
  const Indicators& i = e.indicators;
  std::printf("pressure    eps_p = %.6g   NoP_p = %g   p_max = %.6g MPa (%.4g x rho*c*v0)\n",
              i.eps_p, i.nop_p, i.p_max, i.p_max_ratio);
  std::printf("velocity    eps_v = %.6g   NoP_v = %g\n", i.eps_v, i.nop_v);
  std::printf("contact     %g episode(s); energy at t_end / initial = %.6g\n", i.contact_episodes,
              i.energy_ratio);
  if (const RodScene& rod = *sim.rod(); rod.far_gap) {
    std::printf(
        "far wall    far_gap = %g mm: %g episode(s); %g impact(s) at both walls; largest "
        "penetration of a wall = %.3g mm\n",
        *rod.far_gap, i.far_contact_episodes, i.impacts, i.max_penetration);
  }
  write_tail(e, episodes);
}

}  // namespace

std::function<int()> add_simulate_command(CLI::App& app) {
  auto* command = app.add_subcommand("simulate",
                                     "Run one rod-impact simulation with one method "
                                     "and print the paper's indicators");
  struct Options {
    GivenOptions given;
    SceneOptions scene;
    bool json = false;
    std::string history;
    bool force = false;
  };
  auto options = std::make_shared<Options>();
  add_parameter_options(*command, options->given,
                        {ParameterGroup::method, ParameterGroup::scene, ParameterGroup::output});
  add_scene_options(*command, options->scene);
  command->add_flag("--json", options->json, "Print one JSON object instead of text");
  command
      ->add_option("--history", options->history,
                   "Write the time histories to FILE (.csv, or .h5/.hdf5 for HDF5)")
      ->type_name("FILE");
  command->add_flag("--force", options->force,
                    "Replace the --history file even if it is not a time-history file (a "
                    "results file of impactid run, say)");

  return [command, options]() -> int {
    if (!command->parsed()) return -1;
    SimulationSettings settings;
    if (!apply_scene_options(options->scene, settings, "simulate") ||
        !apply_options(options->given, settings, "simulate")) {
      return kExitBadInput;
    }
    const auto sim = build_or_report(settings, "simulate");
    if (!sim) return kExitBadInput;
    if (!options->history.empty()) {
      const std::string ext = std::filesystem::path(options->history).extension().string();
      if (ext != ".csv" && ext != ".h5" && ext != ".hdf5") {
        std::cerr << "impactid simulate: --history = " << options->history
                  << ": must end in .csv, .h5 or .hdf5\n";
        return kExitBadInput;
      }
      // Another run's histories are replaced; any other file (a study's results) only on
      // request: a mistyped name must not cost a sweep.
      if (std::filesystem::exists(options->history) && !options->force &&
          !is_history_file(options->history)) {
        std::cerr << "impactid simulate: --history = " << options->history
                  << ": exists and is not a time-history file; it was left untouched (choose "
                     "another file, or give --force to replace it)\n";
        return kExitFailure;
      }
    }
    SimulationWorkspace workspace;
    Simulation run = *sim;
    run.run.record_history = !options->history.empty();
    const Evaluation e = evaluate(run, workspace);
    const std::vector<EpisodeComparison> episodes = primary_episodes(run, workspace, e.summary);
    if (options->json) {
      write_json(*sim, e, episodes);
    } else {
      write_text(*sim, e, episodes);
    }
    if (!options->history.empty()) {
      try {
        write_history(options->history, *sim, workspace.trace,
                      workspace.model_reference ? &*workspace.model_reference : nullptr);
      } catch (const std::exception& error) {
        std::cerr << "impactid simulate: " << error.what() << '\n';
        return kExitFailure;
      }
      if (!options->json) std::printf("history     %s\n", options->history.c_str());
    }
    return e.reference_trusted ? 0 : kExitUnverified;
  };
}

std::function<int()> add_compare_command(CLI::App& app) {
  auto* command = app.add_subcommand(
      "compare", "Run every method at its default parameters on one scene and print a table");
  auto given = std::make_shared<GivenOptions>();
  auto scene = std::make_shared<SceneOptions>();
  add_parameter_options(*command, *given, {ParameterGroup::scene, ParameterGroup::output});
  add_scene_options(*command, *scene);

  return [command, given, scene]() -> int {
    if (!command->parsed()) return -1;
    SimulationSettings base;
    if (!apply_scene_options(*scene, base, "compare") || !apply_options(*given, base, "compare")) {
      return kExitBadInput;
    }
    // Every method's run first, then the table sorted by verdict (the order of severity,
    // metrics/verdict.hpp), then by eps_p, then in the registry's order.
    struct Row {
      MethodKind kind;
      std::string params;
      Evaluation e;
    };
    std::vector<Row> rows;
    SimulationWorkspace workspace;
    std::string not_run;  // the methods that do not step the massless DOFs of a modified mass
    std::string not_taking;  // the methods that do not take the contact law
    for (const MethodDescriptor& method : method_registry()) {
      const MethodKind kind = method.kind;
      if (has_massless_dofs(base.scene.mass) &&
          massless_refusal(method, base.scene.rayleigh_stiffness)) {
        not_run += (not_run.empty() ? "" : "|") + std::string(method.name);
        continue;
      }
      if (contact_law_refusal(method, base.run.contact.law)) {
        not_taking += (not_taking.empty() ? "" : "|") + std::string(method.name);
        continue;
      }
      SimulationSettings settings = base;
      settings.method = MethodSettings{.kind = kind};
      const auto sim = build_or_report(settings, "compare");
      if (!sim) return kExitBadInput;
      Evaluation e = evaluate(*sim, workspace);
      std::string params;
      for (const ReportedValue& v : method.values(sim->method)) {
        if (v.derived) continue;
        char buffer[48];
        std::snprintf(buffer, sizeof buffer, "%s%s=%.3g", params.empty() ? "" : " ", v.name,
                      v.value);
        params += buffer;
      }
      if (params.empty()) params = "-";
      rows.push_back({kind, params, std::move(e)});
    }
    std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
      return ranks_before(a.e.verdict, a.e.indicators.eps_p, b.e.verdict, b.e.indicators.eps_p);
    });
    const bool measured = base.model || base.bodies;  // against a computed reference
    std::printf("%-18s %-30s %-8s %-11s %9s %6s %9s %6s %8s %8s %9s%s\n", "method", "parameters",
                "status", "verdict", "eps_p", "NoP_p", "eps_v", "NoP_v", "p_max/pc", "E_end/E0",
                "time[ms]", measured ? "   ref_err" : "");
    bool trusted = true;
    for (const Row& row : rows) {
      const Indicators& i = row.e.indicators;
      std::printf("%-18s %-30s %-8s %-11s %9.4g %6g %9.4g %6g %8.4g %8.4g %9.3g",
                  to_string(row.kind), row.params.c_str(), to_string(row.e.summary.status),
                  to_string(row.e.verdict), i.eps_p, i.nop_p, i.eps_v, i.nop_v, i.p_max_ratio,
                  i.energy_ratio, row.e.summary.wall_time_s * 1e3);
      if (measured) std::printf(" %9.3g", row.e.reference_error);
      std::printf("\n");
      trusted = trusted && row.e.reference_trusted;
    }
    if (!not_run.empty()) {
      std::printf("not run     %s: they do not step the massless contact DOFs of mass = %s\n",
                  not_run.c_str(), to_string(base.scene.mass));
    }
    if (!not_taking.empty()) {
      std::printf("not run     %s: they do not take contact = %s\n", not_taking.c_str(),
                  to_string(base.run.contact.law));
    }
    std::printf("verdicts    accurate within %s\n", thresholds_text(base.verdict).c_str());
    if (!rows.empty() && !rows.front().e.reference.empty()) {
      std::printf("reference   %s\n", rows.front().e.reference.c_str());
    }
    if (!trusted) {
      std::printf("unverified  the reference is not trusted: no verdict above is a result\n");
      return kExitUnverified;
    }
    return 0;
  };
}

}  // namespace impactid
