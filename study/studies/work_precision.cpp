#include "study/studies/work_precision.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "core/model/scene_assembly.hpp"
#include "metrics/indicator_table.hpp"
#include "study/studies/evaluation.hpp"
#include "study/studies/sweep.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Indicators of indicator_table() a work-precision table stores, in this order; wall_time_s
/// holds the minimum over the repeats.
constexpr const char* kIndicators[] = {"eps_p",       "eps_v",        "nop_p",      "nop_v",
                                       "p_max_ratio", "energy_ratio", "wall_time_s"};

/// Parameters stored per point: the step, and each numeric method parameter (NaN where the
/// method has none; β and γ, given or derived, for the Newmark family).
std::vector<const char*> stored_parameters() {
  std::vector<const char*> out{"dt"};
  for (const MethodParameter& p : method_parameters()) {
    if (!p.choice) out.push_back(p.name);
  }
  return out;
}

ResultColumn parameter_column(const char* name, std::size_t size) {
  const ParameterInfo* info = find_parameter(name);
  std::string long_name = info ? info->description : name;
  if (std::string_view(name) == "beta" || std::string_view(name) == "gamma") {
    long_name = std::string("Newmark ") + name +
                " used at the point (eq. 13 from delta, or given); NaN for cdm and "
                "backward-euler";
  }
  return {name, info && *info->unit ? info->unit : "1", long_name, "",
          std::vector<double>(size, kNaN)};
}

}  // namespace

StudyResults empty_work_precision_results(const Plan& plan) {
  const WorkPrecisionStudy& wp = plan.work_precision;
  StudyResults r;
  r.plan_name = plan.name;
  r.plan_text = plan.text;
  r.study_kind = to_string(plan.kind);
  std::vector<double> method_index;
  for (std::size_t m = 0; m < wp.methods.size(); ++m) {
    method_index.push_back(static_cast<double>(m));
    if (m) r.method += ',';
    r.method += to_string(kind_of(wp.methods[m].params));
  }
  r.dimensions.push_back({"method", "1", method_index});
  r.dimensions.push_back(
      {"elements", "1", std::vector<double>(wp.elements.begin(), wp.elements.end())});
  r.dimensions.push_back({"courant", "1", wp.courant});
  const std::size_t size = wp.methods.size() * wp.elements.size() * wp.courant.size();
  r.status.assign(size, kStatusNotDone);
  for (const char* name : stored_parameters()) {
    r.parameters.push_back(parameter_column(name, size));
  }
  for (const char* name : kIndicators) {
    const IndicatorInfo* info = find_indicator(name);
    assert(info);
    r.indicators.push_back(
        {name, info->units, name, info->definition, std::vector<double>(size, kNaN)});
  }
  ResultColumn& wall = r.indicators.back();
  wall.long_name = "wall_time_s: the fastest of the repeats";
  wall.definition =
      "minimum over `repeats` runs, one at a time on one thread, of the simulation's wall-clock "
      "time (set-up and stepping, not the indicators); kept whatever the status";
  r.indicators.push_back(
      {"wall_time_max_s", "s", "wall_time_max_s: the slowest of the repeats",
       "maximum over the repeats of the same time: max/min shows the timing noise; kept "
       "whatever the status",
       std::vector<double>(size, kNaN)});
  r.indicators.push_back({"steps", "1", "time steps completed",
                          "samples t_i = i*dt completed (N for an ok run; fewer for a run that "
                          "stopped); kept whatever the status",
                          std::vector<double>(size, kNaN)});
  r.indicators.push_back(
      {"dof_steps", "1", "degree-of-freedom updates computed",
       "(steps - free-flight steps filled in rather than computed) * (elements + 1): the work "
       "of the run, independent of the machine; kept whatever the status",
       std::vector<double>(size, kNaN)});
  add_reference_columns(plan.base, size, r);

  for (std::size_t m = 0; m < wp.methods.size(); ++m) {
    r.text_attributes.emplace_back("method_label_" + std::to_string(m), wp.methods[m].label);
  }
  r.numeric_attributes.emplace_back("repeats", static_cast<double>(wp.repeats));
  r.text_attributes.emplace_back(
      "timing",
      "wall_time_s is the minimum of `repeats` runs of each point, points one at a time on one "
      "thread");
  add_verdict_column(plan.base, size, r);  // after the study's own attributes, as it came later
  return r;
}

SweepOutcome run_work_precision(const Plan& plan, StudyResults& results,
                                const WorkPrecisionOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const WorkPrecisionStudy& wp = plan.work_precision;

  SweepOutcome outcome;
  long todo = 0;
  for (const int status : results.status) {
    if (status == kStatusNotDone) {
      ++todo;
    } else {
      ++outcome.reused;
    }
  }
  // Columns looked up once; the table was made by empty_work_precision_results().
  struct StoredIndicator {
    ResultColumn* column;
    const IndicatorInfo* info;
  };
  std::vector<StoredIndicator> stored;
  for (const char* name : kIndicators) {
    stored.push_back({results.find_column(name), find_indicator(name)});
  }
  ResultColumn* wall_min = results.find_column("wall_time_s");
  ResultColumn* wall_max = results.find_column("wall_time_max_s");
  ResultColumn* steps = results.find_column("steps");
  ResultColumn* dof_steps = results.find_column("dof_steps");

  SimulationWorkspace workspace;  // reused: after the first run of a size, no allocation
  auto last_checkpoint = Clock::now();
  auto last_progress = Clock::now();
  long done = 0, unstable = 0;
  const auto n_elements = static_cast<long>(wp.elements.size());
  const auto n_courant = static_cast<long>(wp.courant.size());
  for (long index = 0; index < results.points_total(); ++index) {
    const auto i = static_cast<std::size_t>(index);
    if (results.status[i] != kStatusNotDone) continue;
    if (options.stop && options.stop->load()) break;
    const long m = index / (n_elements * n_courant);
    const auto e = static_cast<std::size_t>(index / n_courant % n_elements);
    const auto c = static_cast<std::size_t>(index % n_courant);
    const auto built = build(work_precision_settings(plan, m, wp.elements[e], wp.courant[c]));
    const Simulation& simulation = std::get<Simulation>(built);  // checked by load_plan()

    const Evaluation evaluation = evaluate(simulation, workspace);
    double fastest = evaluation.summary.wall_time_s, slowest = fastest;
    const std::optional<AssembledScene> assembled = std::visit(
        Overloaded{[](const RodScene&) { return std::optional<AssembledScene>(); },
                   [](const auto& scene) { return std::optional(assemble(scene)); }},
        simulation.scene);
    for (int repeat = 1; repeat < wp.repeats; ++repeat) {
      const RunSummary again =
          assembled ? simulate(*assembled, simulation.method, simulation.run, workspace)
                    : simulate(*simulation.rod(), simulation.method, simulation.run, workspace);
      assert(again.status == evaluation.summary.status && again.steps == evaluation.summary.steps);
      fastest = std::min(fastest, again.wall_time_s);
      slowest = std::max(slowest, again.wall_time_s);
    }

    results.status[i] = static_cast<int>(evaluation.summary.status);
    for (ResultColumn& p : results.parameters) {
      p.values[i] = numeric_value(simulation, p.name).value_or(kNaN);
    }
    for (const StoredIndicator& s : stored) s.column->values[i] = s.info->value(evaluation);
    store_reference_columns(results, i, evaluation);
    store_verdict(results, i, evaluation);
    wall_min->values[i] = fastest;
    wall_max->values[i] = slowest;
    steps->values[i] = static_cast<double>(evaluation.summary.steps);
    dof_steps->values[i] =
        static_cast<double>(evaluation.summary.steps - evaluation.summary.skipped_steps) *
        static_cast<double>(std::visit(
            Overloaded{[](const RodScene& rod) { return static_cast<long>(rod.elements) + 1; },
                       [](const Scene& bodies) { return derive(bodies).nodes; },
                       [](const ModelScene& model) { return static_cast<long>(model.model->size()); }},
            simulation.scene));

    ++done;
    if (evaluation.summary.status != RunStatus::ok) ++unstable;
    if (options.checkpoint && seconds_since(last_checkpoint) >= options.checkpoint_seconds) {
      options.checkpoint(results);
      last_checkpoint = Clock::now();
    }
    if (options.progress && seconds_since(last_progress) >= options.progress_seconds) {
      options.progress({done, todo, unstable, seconds_since(start)});
      last_progress = Clock::now();
    }
  }
  outcome.computed = done;
  outcome.unstable = unstable;
  outcome.interrupted = done < todo;
  outcome.wall_time_s = seconds_since(start);
  if (options.progress) options.progress({done, todo, unstable, outcome.wall_time_s});
  return outcome;
}

}  // namespace impactid
