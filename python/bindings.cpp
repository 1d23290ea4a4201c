// The C++ side of `import impactid` (python/impactid/__init__.py is the API users call): thin
// wrappers of the study layer that the command line uses, so that a Python call and the command
// with the same parameters run the same code and give the same numbers. Values cross as plain
// Python objects (dicts, lists, NumPy arrays); scenes and plans as TOML text, which the Python
// side writes from dicts. The GIL is released while a simulation or a plan runs.
//
// Errors: a bad parameter raises impactid.ParameterError (a ValueError) with the settings
// layer's field, value and constraint, the words of the command line's message; a bad plan or
// scene raises ValueError with the plan reader's message, the command line's exact text.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/common/kernel_level.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/model_reference.hpp"
#include "metrics/indicator_table.hpp"
#include "study/cli/command_line.hpp"
#include "study/cli/methods_command.hpp"
#include "study/cli/run_command.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/io/history_file.hpp"
#include "study/io/results_file.hpp"
#include "study/plan/plan.hpp"
#include "study/studies/damping_match.hpp"
#include "study/studies/evaluation.hpp"
#include "study/studies/spectral_report.hpp"
#include "study/version.hpp"

namespace py = pybind11;

namespace impactid::python {
namespace {

// impactid.ParameterError, set by the package when it imports this module.
py::handle g_parameter_error_class;

struct ParameterErrorRaised {
  ParameterError error;
};

[[noreturn]] void raise(const ParameterError& error) {
  throw ParameterErrorRaised{error};
}

// Parameters by name, as the Python side passes them (a str for a choice, a float otherwise).
using Given = std::vector<std::pair<std::string, ParameterValue>>;

// The settings of a scene file, of a [scene] table written as TOML (`scene_text`, named
// `scene_source` in messages), or the defaults; then the dotted keys (`set`), then the
// parameters, in the order the command line applies its options (by name: a std::map).
SimulationSettings settings_of(const std::optional<std::string>& scene_file,
                               const std::optional<std::string>& scene_text,
                               const std::string& scene_source, const Given& set,
                               const Given& params) {
  SimulationSettings settings;
  try {
    if (scene_file) settings = load_scene_file(*scene_file);
    if (scene_text) settings = parse_scene_file(*scene_text, scene_source);
  } catch (const PlanError& error) {
    throw py::value_error(error.what());
  }
  for (const auto& [key, value] : set) {
    if (auto error = assign(settings, key, value)) raise(*error);
  }
  const std::map<std::string, ParameterValue> sorted(params.begin(), params.end());
  for (const auto& [name, value] : sorted) {
    if (auto error = assign(settings, name, value)) raise(*error);
  }
  return settings;
}

Simulation build_or_raise(const SimulationSettings& settings) {
  auto built = build(settings);
  if (const auto* error = std::get_if<ParameterError>(&built)) raise(*error);
  return std::get<Simulation>(std::move(built));
}

py::array_t<double> array_of(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// A value that is a result only when it is finite; None otherwise (never a NaN as a result).
py::object finite_or_none(double v) {
  if (std::isfinite(v)) return py::float_(v);
  return py::none();
}

// Every parameter the run used (derived δ, β, γ and generalized-α's α_m, α_f included) and its
// choice parameters, as `impactid simulate --json` reports them.
py::dict used_parameters(const Simulation& sim) {
  py::dict out;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.kind == ParameterKind::choice) continue;
    // A NaN is a value that is not set (penalty_stiffness under Lagrange's law): left out.
    const auto value = numeric_value(sim, info.name);
    if (value && std::isfinite(*value)) out[info.name] = *value;
  }
  out["mass"] = to_string(mass_key(sim));
  const MethodDescriptor& method = descriptor(sim.method);
  for (const auto& [name, word] : method.choices(sim.method)) out[name] = word;
  for (const ReportedValue& v : method.values(sim.method)) {
    if (!find_parameter(v.name)) out[v.name] = v.value;
  }
  return out;
}

// One run as the Python Run object is made from: what `impactid simulate --json` reports, the
// indicators only for a run that finished ("ok"), and the columns of its --history file.
py::dict run_dict(const Simulation& sim, const Evaluation& e,
                  const SimulationWorkspace& workspace) {
  py::dict out;
  out["method"] = to_string(kind_of(sim.method));
  out["parameters"] = used_parameters(sim);
  out["dt"] = e.summary.dt;
  out["steps"] = e.summary.steps;
  out["planned_steps"] = e.summary.planned_steps;
  out["status"] = to_string(e.summary.status);
  out["verdict"] = to_string(e.verdict);
  out["verdict_reason"] =
      verdict_reason(e.summary.status, e.indicators, e.reference_trusted, sim.verdict);
  out["message"] = e.summary.message;
  out["warning"] = e.summary.warning;
  out["contact"] = to_string(sim.run.contact.law);
  if (descriptor(sim.run.contact.law).springs) {
    out["contact_iterations"] = e.summary.contact_iterations;
    out["unconverged_contact_steps"] = e.summary.unconverged_contact_steps;
    out["stable_dt"] = finite_or_none(e.summary.stable_dt);
  }
  out["wall_time_s"] = e.summary.wall_time_s;
  const bool ok = e.summary.status == RunStatus::ok;
  py::dict indicators;
  for (const IndicatorInfo& info : indicator_table()) {
    if (std::string_view(info.name) == "wall_time_s") continue;
    const double v = info.value(e);
    if (ok && std::isfinite(v)) indicators[info.name] = v;  // NaN: not applicable to the scene
  }
  out["indicators"] = indicators;
  if (const RodScene* rod = sim.rod()) out["pressure_scale"] = derive(*rod).pressure_scale;
  py::list contacts;
  std::vector<std::string> names;
  if (sim.bodies()) {
    for (const SceneContact& c : scene_contacts(*sim.bodies())) names.push_back(c.name);
    out["primary_contact"] = names[static_cast<std::size_t>(derive(*sim.bodies()).primary_contact)];
  } else if (sim.model()) {
    for (const ModelContact& c : sim.model()->model->contacts) names.push_back(c.name);
    out["primary_contact"] = names[static_cast<std::size_t>(primary_contact_index(*sim.model()))];
  }
  for (std::size_t k = 0; k < names.size() && k < e.contacts.size(); ++k) {
    const ContactIndicators& c = e.contacts[k];
    py::dict contact;
    contact["name"] = names[k];
    if (ok) {
      const std::pair<const char*, double> values[] = {{"eps_p", c.eps_p},
                                                       {"eps_v", c.eps_v},
                                                       {"nop_p", c.nop_p},
                                                       {"nop_v", c.nop_v},
                                                       {"p_max", c.p_max},
                                                       {"p_max_ratio", c.p_max_ratio},
                                                       {"contact_episodes", c.contact_episodes}};
      for (const auto& [name, v] : values) {
        if (std::isfinite(v)) contact[name] = v;
      }
    }
    contacts.append(contact);
  }
  out["contacts"] = contacts;
  out["reference"] = e.reference;
  out["reference_trusted"] = e.reference_trusted;
  out["reference_error"] = finite_or_none(e.reference_error);
  // The primary contact's episodes beside the reference's (metrics/episodes.hpp), as
  // `impactid simulate --json` lists them; a time missing (no contact in a window) is None.
  py::list episodes;
  for (const EpisodeComparison& c : primary_episodes(sim, workspace, e.summary)) {
    py::dict episode;
    episode["start"] = finite_or_none(c.start);
    episode["reference_start"] = c.reference_start;
    episode["end"] = finite_or_none(c.end);
    episode["reference_end"] = c.reference_end;
    episode["impulse"] = c.impulse;
    episode["reference_impulse"] = c.reference_impulse;
    episode["peaks"] = c.peaks;
    episode["contact_runs"] = c.contact_runs;
    episode["energy_ratio"] = finite_or_none(c.energy_ratio);
    episodes.append(episode);
  }
  out["episodes"] = episodes;
  py::list history;
  for (const HistoryColumn& c :
       history_columns(sim, workspace.trace, sim.model() ? &*workspace.model_reference : nullptr)) {
    history.append(py::make_tuple(c.name, c.units, c.description, array_of(c.values)));
  }
  out["history"] = history;
  return out;
}

// `impactid simulate`: one scene, one method, with its time histories.
py::dict simulate(const std::optional<std::string>& scene_file,
                  const std::optional<std::string>& scene_text, const std::string& scene_source,
                  const Given& set, const Given& params) {
  Simulation sim = build_or_raise(settings_of(scene_file, scene_text, scene_source, set, params));
  sim.run.record_history = true;
  SimulationWorkspace workspace;
  Evaluation e;
  {
    py::gil_scoped_release release;
    e = evaluate(sim, workspace);
  }
  return run_dict(sim, e, workspace);
}

// `impactid compare`: every method at its default parameters on one scene, in the registry's
// order.
py::list compare(const std::optional<std::string>& scene_file,
                 const std::optional<std::string>& scene_text, const std::string& scene_source,
                 const Given& set, const Given& params) {
  const SimulationSettings base = settings_of(scene_file, scene_text, scene_source, set, params);
  // In the command's order: by verdict, then by eps_p (metrics/verdict.hpp: ranks_before).
  std::vector<std::tuple<Verdict, double, py::dict>> runs;
  SimulationWorkspace workspace;
  for (const MethodDescriptor& method : method_registry()) {
    SimulationSettings settings = base;
    settings.method = MethodSettings{.kind = method.kind};
    Simulation sim = build_or_raise(settings);
    sim.run.record_history = true;
    Evaluation e;
    {
      py::gil_scoped_release release;
      e = evaluate(sim, workspace);
    }
    runs.emplace_back(e.verdict, e.indicators.eps_p, run_dict(sim, e, workspace));
  }
  std::stable_sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) {
    return ranks_before(std::get<0>(a), std::get<1>(a), std::get<0>(b), std::get<1>(b));
  });
  py::list out;
  for (auto& run : runs) out.append(std::get<2>(run));
  return out;
}

py::dict spectral_dict(const SpectralReport& r) {
  py::dict out;
  out["method"] = to_string(kind_of(r.simulation.method));
  py::dict parameters;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.group != ParameterGroup::method || info.kind == ParameterKind::choice) continue;
    if (const auto v = numeric_value(r.simulation, info.name)) parameters[info.name] = *v;
  }
  out["parameters"] = parameters;
  out["rho_inf"] = r.rho_inf;
  out["period_error_coefficient"] = r.period_error_coefficient;
  py::dict stability;
  stability["omega_min"] = std::min(kStabilityScanMinOmega, r.omega_max);
  stability["omega_max"] = r.omega_max;
  stability["omega_max_from"] = r.omega_max_from;
  stability["max_spectral_radius"] = r.max_rho;
  stability["stable"] = r.stable;
  out["stability"] = stability;
  if (r.alpha) {
    py::dict delta_min;
    delta_min["limit"] = r.delta_min_limit;
    delta_min["eq19"] = -1.5 * *r.alpha;
    out["delta_min_period_error"] = delta_min;
  }
  std::vector<double> omega, rho, xi, period;
  std::vector<double> delta_min;
  std::vector<bool> oscillatory;
  for (const SpectralAtOmega& a : r.at) {
    omega.push_back(a.omega_dt);
    rho.push_back(a.properties.spectral_radius);
    xi.push_back(a.properties.damping_ratio);
    period.push_back(a.properties.period_error);
    oscillatory.push_back(a.properties.oscillatory);
    delta_min.push_back(a.delta_min);
  }
  out["omega_dt"] = array_of(omega);
  out["spectral_radius"] = array_of(rho);
  out["damping_ratio"] = array_of(xi);
  out["period_error"] = array_of(period);
  out["oscillatory"] = oscillatory;
  if (r.alpha) out["delta_min"] = array_of(delta_min);
  return out;
}

// `impactid spectral`: the method's spectral analysis. `omega_max` and `omega_dt` were checked by
// the Python side; courant and mass among `params` set Ω_max to the rod's highest mode.
py::dict spectral(const Given& params, const std::vector<double>& omega_dt,
                  std::optional<double> omega_max) {
  const Simulation sim = build_or_raise(settings_of({}, {}, "", {}, params));
  bool scene_given = false;
  for (const auto& [name, value] : params) scene_given |= name == "courant" || name == "mass";
  return spectral_dict(spectral_report(sim, omega_max, scene_given, omega_dt));
}

// `impactid spectral --match-damping XI --omega-dt W`.
py::dict match(double target, double omega_dt) {
  py::dict out;
  out["omega_dt"] = omega_dt;
  out["damping_ratio"] = target;
  py::list matches;
  for (const DampingFamilyInfo& f : damping_families()) {
    const DampingMatch m = match_damping(f.family, omega_dt, target);
    py::dict d;
    d["family"] = f.name;
    d["method"] = family_method(m.family);
    d["parameter"] = f.parameter;
    d["reachable"] = m.reachable;
    d["value"] = finite_or_none(m.parameter);
    d["damping_ratio"] = m.reachable ? py::object(py::float_(m.damping_ratio)) : py::none();
    if (m.reachable) {
      py::dict parameters;
      for (const auto& [name, v] : family_parameters(m.family, m.parameter)) parameters[name] = v;
      d["parameters"] = parameters;
    } else {
      d["parameters"] = py::none();
    }
    d["range"] = py::make_tuple(f.undamped_end, f.damped_end);
    d["attainable"] =
        py::make_tuple(finite_or_none(m.attainable_min), finite_or_none(m.attainable_max));
    d["roots"] = m.roots;
    matches.append(d);
  }
  out["matches"] = matches;
  py::dict fixed;
  for (const auto& [name, params] : fixed_damping_methods()) {
    fixed[name] = spectral_properties(params, omega_dt).damping_ratio + 0.0;  // -0 as 0
  }
  out["fixed"] = fixed;
  return out;
}

// The results file a plan writes: `output`, else the plan's [output] file. Raises ValueError
// with the plan reader's message for a bad plan.
std::string plan_output(const std::string& plan_path, const std::string& plan_text,
                        const std::string& output) {
  try {
    const Plan plan = plan_text.empty() ? load_plan(plan_path) : parse_plan(plan_text, plan_path);
    return output.empty() ? plan.output.file.string() : output;
  } catch (const PlanError& error) {
    throw py::value_error(error.what());
  }
}

// Holds std::cerr's output while it lives: the run command reports its errors there, and the
// Python side raises them instead.
class CaptureErrors {
 public:
  CaptureErrors() : previous_(std::cerr.rdbuf(text_.rdbuf())) {}
  ~CaptureErrors() { std::cerr.rdbuf(previous_); }
  CaptureErrors(const CaptureErrors&) = delete;
  CaptureErrors& operator=(const CaptureErrors&) = delete;
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::streambuf* previous_;
};

// `impactid run`: the same function, with the GIL released. Returns its exit status and what it
// wrote to std::cerr (progress and the summary still go to stderr).
py::tuple run_plan_file(const std::string& plan_path, const std::string& plan_text,
                        const std::string& output, int threads, bool resume) {
  const RunArguments args{.plan = plan_path,
                          .plan_text = plan_text,
                          .output = output,
                          .threads = threads,
                          .resume = resume};
  int status = 0;
  std::string errors;
  {
    py::gil_scoped_release release;
    CaptureErrors capture;
    status = run_plan(args);
    errors = capture.text();
  }
  return py::make_tuple(status, errors);
}

py::list parameters() {
  py::list out;
  for (const ParameterInfo& info : parameter_table()) {
    py::dict d;
    d["name"] = info.name;
    d["group"] = info.group == ParameterGroup::scene    ? "scene"
                 : info.group == ParameterGroup::method ? "method"
                                                        : "output";
    d["kind"] = info.kind == ParameterKind::real      ? "real"
                : info.kind == ParameterKind::integer ? "integer"
                                                      : "choice";
    d["unit"] = info.unit;
    d["description"] = info.description;
    d["choices"] = info.choices;
    d["methods"] = info.methods;
    out.append(d);
  }
  return out;
}

}  // namespace
}  // namespace impactid::python

PYBIND11_MODULE(_impactid, m) {
  using namespace impactid;
  using namespace impactid::python;
  m.doc() = "impactid's C++ core; use the impactid package, not this module";
  // A kernel level the processor lacks (IMPACTID_KERNELS) is refused at import, as the program
  // refuses it at start (core/common/kernel_level.hpp).
  if (const KernelSelection& kernels = kernel_selection(); !kernels.error.empty()) {
    throw std::runtime_error("impactid: " + kernels.error);
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ParameterErrorRaised& raised) {
      const ParameterError& e = raised.error;
      const py::object args = py::make_tuple(e.field, e.value, e.constraint);
      PyErr_SetObject(g_parameter_error_class ? g_parameter_error_class.ptr() : PyExc_ValueError,
                      args.ptr());
    }
  });
  m.def("set_parameter_error_class", [](py::handle cls) {
    // Kept for the life of the process: the class outlives every call that raises it.
    g_parameter_error_class = cls.inc_ref();
  });
  m.def("simulate", &python::simulate);
  m.def("compare", &python::compare);
  m.def("spectral", &python::spectral);
  m.def("match_damping", &python::match);
  m.def("plan_output", &python::plan_output);
  m.def("run_plan", &python::run_plan_file);
  // open_results's checks: read_results, as `impactid export`, `merge` and `run --resume` read
  // a file (format, checksums, status codes, axes), its message in a ValueError.
  m.def("check_results", [](const std::string& path) {
    try {
      read_results(path);
    } catch (const Hdf5Error& e) {
      throw py::value_error(e.what());
    }
  });
  m.def("parameters", &python::parameters);
  m.def("version", [] { return std::string(kVersion) + "+" + kGitRevision; });
  m.def("kernels", [] { return describe_kernel_selection(); });
  m.def("methods", [] {
    std::vector<std::string> names;
    for (const MethodDescriptor& d : method_registry()) names.emplace_back(d.name);
    return names;
  });
  // `impactid methods --json`'s text: the figures' method labels, parameters and colour order
  // when impactid.plot draws in this process (python/impactid/_plot.py).
  m.def("methods_json", [] {
    std::ostringstream out;
    write_methods_json(out);
    return out.str();
  });
  m.def("contact_laws", [] {
    std::vector<std::string> names;
    for (const ContactLawDescriptor& d : contact_law_registry()) names.emplace_back(d.name);
    return names;
  });
  m.def("indicators", [] {
    std::vector<std::string> names;
    for (const IndicatorInfo& i : indicator_table()) names.emplace_back(i.name);
    return names;
  });
}
