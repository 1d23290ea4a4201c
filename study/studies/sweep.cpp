#include "study/studies/sweep.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <span>
#include <variant>

#include "metrics/indicator_table.hpp"
#include "study/plan/scene_path.hpp"
#include "study/studies/first_failure.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The indicators every contact of a scene of bodies has (metrics ContactIndicators), by name;
// nothing for the others.
std::optional<double> contact_indicator(const std::string& name, const ContactIndicators& c) {
  if (name == "eps_p") return c.eps_p;
  if (name == "eps_v") return c.eps_v;
  if (name == "nop_p") return c.nop_p;
  if (name == "nop_v") return c.nop_v;
  if (name == "p_max") return c.p_max;
  if (name == "p_max_ratio") return c.p_max_ratio;
  if (name == "contact_episodes") return c.contact_episodes;
  return std::nullopt;
}
bool contact_indicator(const std::string& name) {
  return contact_indicator(name, ContactIndicators{}).has_value();
}

// The names of a scene's contacts: a scene of bodies' or a model's; none for the rod (whose
// indicators are its one contact's).
std::vector<std::string> contact_names(const Scene* bodies, const ModelScene* model) {
  std::vector<std::string> names;
  if (bodies) {
    for (const SceneContact& c : scene_contacts(*bodies)) names.push_back(c.name);
  } else if (model) {
    for (const ModelContact& c : model->model->contacts) names.push_back(c.name);
  }
  return names;
}
std::vector<std::string> contact_names(const SimulationSettings& s) {
  return contact_names(s.bodies ? &*s.bodies : nullptr, s.model ? &*s.model : nullptr);
}
std::vector<std::string> contact_names(const Simulation& s) {
  return contact_names(s.bodies(), s.model());
}

bool is_dimension(const PointSet& points, const std::string& name) {
  const auto& dims = points.dimension_names();
  return std::find(dims.begin(), dims.end(), name) != dims.end();
}

// The unit of a parameter or of a scene of bodies' dotted key.
const char* parameter_units(const std::string& name) {
  if (is_scene_path(name)) return scene_path_units(name);
  const ParameterInfo* info = find_parameter(name);
  return info && *info->unit ? info->unit : "1";
}

ResultColumn parameter_column(const std::string& name, std::size_t size) {
  const ParameterInfo* info = find_parameter(name);
  return {name, parameter_units(name), info ? info->description : name, "",
          std::vector<double>(size, kNaN)};
}

}  // namespace

void add_reference_columns(const SimulationSettings& base, std::size_t size, StudyResults& r) {
  // A scene of bodies records its reference at every point: 0 refinements for the exact
  // solution, k for a converged one at h/2^k and dt/2^k (a damped scene), with the change at
  // the last.
  if (base.bodies) {
    r.indicators.push_back(
        {"reference_refinements", "1", "reference_refinements",
         "0: an exact solution (of the chain, core/reference/chain_exact.hpp, or of the clamped "
         "bar, core/reference/clamped_bar_exact.hpp); k >= 1: "
         "a converged numerical solution at h/2^k and dt/2^k (core/reference/scene_reference.hpp)",
         std::vector<double>(size, kNaN)});
    r.indicators.push_back({"reference_change", "1", "reference_change",
                            "relative change of the converged reference's primary contact at its "
                            "last halving of the mesh and the step; NaN for the exact solution",
                            std::vector<double>(size, kNaN)});
  }
  // A user's model records its reference the same way (−1: the supplied history), with the
  // reference's step; the model's units and files are attributes.
  if (base.model) {
    r.indicators.push_back(
        {"reference_refinements", "1", "reference_refinements",
         "-1: the reference history supplied with the model; k >= 1: a converged numerical "
         "solution at dt/2^k (core/reference/model_reference.hpp)",
         std::vector<double>(size, kNaN)});
    r.indicators.push_back({"reference_change", "1", "reference_change",
                            "relative change of the converged reference's primary contact at its "
                            "last halving of the step; NaN for a supplied history",
                            std::vector<double>(size, kNaN)});
    r.indicators.push_back({"reference_dt", "s", "reference_dt",
                            "time step of the converged reference; NaN for a supplied history",
                            std::vector<double>(size, kNaN)});
    r.indicators.push_back(
        {"reference_error", "1", "reference_error",
         "estimated error of the converged reference: the larger of its last change and its "
         "difference from the check method's converged solution, eq. 18's form on the primary "
         "contact (core/reference/model_reference.hpp); NaN for a supplied history",
         std::vector<double>(size, kNaN)});
    const Model& model = *base.model->model;
    r.text_attributes.emplace_back("model_units", model.units);
    r.text_attributes.emplace_back("model_files", model.source);
    r.numeric_attributes.emplace_back("model_dofs", static_cast<double>(model.size()));
  }
}

void store_reference_columns(StudyResults& results, std::size_t i, const Evaluation& evaluation) {
  for (ResultColumn& column : results.indicators) {
    if (column.name == "reference_refinements") column.values[i] = evaluation.reference_refinements;
    if (column.name == "reference_change") column.values[i] = evaluation.reference_change;
    if (column.name == "reference_dt") column.values[i] = evaluation.reference_dt;
    if (column.name == "reference_error") column.values[i] = evaluation.reference_error;
  }
}

void add_verdict_column(const SimulationSettings& base, std::size_t size, StudyResults& r) {
  std::string codes;
  for (std::size_t k = 0; k < all_verdicts().size(); ++k) {
    codes += (k ? ", " : "") + std::to_string(k) + " " + to_string(all_verdicts()[k]);
  }
  r.indicators.push_back(
      {kVerdictColumn, "1", "verdict of the run (metrics/verdict.hpp)",
       codes +
           "; NaN not done. From the status, the primary contact's eps_p, nop_p, eps_v, nop_v "
           "and whether the reference is trusted, with the thresholds " +
           thresholds_text(base.verdict),
       std::vector<double>(size, kNaN)});
  r.text_attributes.emplace_back("verdict_thresholds", thresholds_text(base.verdict));
}

void store_verdict(StudyResults& results, std::size_t i, const Evaluation& evaluation) {
  if (ResultColumn* column = results.find_column(kVerdictColumn)) {
    column->values[i] = static_cast<double>(evaluation.verdict);
  }
}

std::string verdict_summary(const StudyResults& results) {
  const ResultColumn* column = results.find_column(kVerdictColumn);
  if (!column) return "";
  std::vector<long> counts(all_verdicts().size(), 0);
  for (const double v : column->values) {
    if (v >= 0 && v < static_cast<double>(counts.size())) ++counts[static_cast<std::size_t>(v)];
  }
  std::string out;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    if (counts[k] == 0) continue;
    out +=
        (out.empty() ? "" : ", ") + std::to_string(counts[k]) + " " + to_string(all_verdicts()[k]);
  }
  return out;
}

StudyResults empty_results(const Plan& plan, const PointSet& points) {
  return empty_results(plan, points, static_cast<std::size_t>(points.size()));
}

StudyResults empty_results(const Plan& plan, const PointSet& points, std::size_t rows) {
  StudyResults r;
  r.plan_name = plan.name;
  r.plan_text = plan.text;
  r.study_kind = to_string(plan.kind);
  r.method = to_string(plan.base.method.kind);
  const std::size_t size = rows;
  for (std::size_t d = 0; d < points.dimension_names().size(); ++d) {
    const std::string& name = points.dimension_names()[d];
    r.dimensions.push_back(
        {name, parameter_units(name), points.dimension_values()[d], points.dimension_labels()[d]});
  }
  r.status.assign(size, kStatusNotDone);
  for (const std::string& name : points.parameter_names()) {
    if (!is_dimension(points, name)) r.parameters.push_back(parameter_column(name, size));
  }
  for (const char* derived : {"beta", "gamma"}) {
    if (!is_dimension(points, derived) &&
        std::none_of(r.parameters.begin(), r.parameters.end(),
                     [&](const ResultColumn& c) { return c.name == derived; })) {
      ResultColumn column = parameter_column(derived, size);
      column.long_name = std::string("Newmark ") + derived +
                         " used at the point (eq. 13 from delta, or given); NaN for cdm and "
                         "backward-euler";
      r.parameters.push_back(std::move(column));
    }
  }
  for (const std::string& name : plan.output.indicators) {
    const IndicatorInfo* info = find_indicator(name);
    r.indicators.push_back(
        {name, info->units, name, info->definition, std::vector<double>(size, kNaN)});
  }
  add_reference_columns(plan.base, size, r);
  add_verdict_column(plan.base, size, r);
  // A scene of several contacts: each contact's indicators beside the primary's, as
  // "<indicator>.<contact>" (the contacts are the same at every point: axes change numbers only).
  const std::vector<std::string> contacts = contact_names(plan.base);
  if (contacts.size() > 1) {
    for (const std::string& contact : contacts) {
      for (const std::string& name : plan.output.indicators) {
        const IndicatorInfo* info = find_indicator(name);
        if (!contact_indicator(name)) continue;
        r.indicators.push_back({name + "." + contact, info->units, name + " at contact " + contact,
                                std::string(info->definition) + " (at contact " + contact + ")",
                                std::vector<double>(size, kNaN)});
      }
    }
  }
  return r;
}

void store_point(StudyResults& results, const PointSet& points, long index,
                 const Simulation& simulation, const Evaluation& evaluation) {
  store_point_row(results, static_cast<std::size_t>(index), points, index, simulation, evaluation);
}

void store_point_row(StudyResults& results, std::size_t row, const PointSet& points, long index,
                     const Simulation& simulation, const Evaluation& evaluation) {
  const std::size_t i = row;
  results.status[i] = static_cast<int>(evaluation.summary.status);
  const std::vector<double> varied = points.parameter_values(index);
  for (ResultColumn& column : results.parameters) {
    const auto& names = points.parameter_names();
    const auto it = std::find(names.begin(), names.end(), column.name);
    if (it != names.end()) {
      column.values[i] = varied[static_cast<std::size_t>(it - names.begin())];
    } else {
      column.values[i] = numeric_value(simulation, column.name).value_or(kNaN);
    }
  }
  store_reference_columns(results, i, evaluation);
  store_verdict(results, i, evaluation);
  const std::vector<std::string> contacts = contact_names(simulation);
  for (ResultColumn& column : results.indicators) {
    if (const IndicatorInfo* info = find_indicator(column.name)) {
      column.values[i] = info->value(evaluation);
      continue;
    }
    if (column.name.starts_with("reference_")) continue;  // store_reference_columns
    if (column.name == kVerdictColumn) continue;          // store_verdict
    // "<indicator>.<contact>" of a scene of bodies (empty_results).
    const std::size_t dot = column.name.find('.');
    const std::string contact = column.name.substr(dot + 1);
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      if (contacts[k] == contact && k < evaluation.contacts.size()) {
        column.values[i] = *contact_indicator(column.name.substr(0, dot), evaluation.contacts[k]);
      }
    }
  }
}

void evaluate_window(const PointSet& points, std::span<const long> window,
                     WindowWorkspace& workspace) {
  const std::size_t size = window.size();
  auto& simulations = workspace.simulations;
  auto& evaluations = workspace.evaluations;
  for (std::size_t k = 0; k < size; ++k) {
    // load_plan() checked every point, so a failure here is a bug, not bad input.
    simulations[k] = std::get<Simulation>(build(points.settings(window[k])));
  }
  for (std::size_t begin = 0, end = 0; begin < size; begin = end) {
    end = begin + 1;
    while (end < size && batchable_together(simulations[begin], simulations[end])) ++end;
    if (end - begin == 1) {
      evaluations[begin] = evaluate(simulations[begin], workspace.single);
    } else {
      evaluate_batch(std::span(simulations).subspan(begin, end - begin), workspace.batch,
                     std::span(evaluations).subspan(begin, end - begin));
    }
  }
}

std::vector<long> points_to_compute(std::span<const long> indices, const StudyResults& results,
                                    long& reused) {
  std::vector<long> todo;
  for (const long index : indices) {
    if (results.status[static_cast<std::size_t>(index)] == kStatusNotDone) {
      todo.push_back(index);
    } else {
      ++reused;
    }
  }
  return todo;
}

SweepOutcome run_sweep(const PointSet& points, std::span<const long> indices, StudyResults& results,
                       const SweepOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };

  SweepOutcome outcome;
  const std::vector<long> todo = points_to_compute(indices, results, outcome.reused);

  // The points to compute are taken kBatchLanes at a time, in order: a thread builds the points
  // of the window it takes, runs them and stores them. Built all at once before the runs, two
  // arrays of 200 bytes per point were written once and read once, and their first touch alone
  // (page faults) cost a few per cent of a sweep (docs/performance.md).
  //
  // Within a window, consecutive points that can share a batch (study/studies/evaluation.hpp:
  // batchable_together) run as one unit through the SIMD kernel; any other point is a unit of
  // its own. A point's numbers are the same either way, so the grouping changes only the speed.
  // (A run of batchable points that does not start at a window's first point is split across two
  // windows: only plans that mix methods or rods along their fastest axis lose lanes to that.)
  std::mutex results_mutex;  // guards `results` and the counters below
  long done = 0, unstable = 0;
  auto last_checkpoint = Clock::now();
  auto last_progress = Clock::now();
  const long count = static_cast<long>(todo.size());
  const long window_count = (count + kBatchLanes - 1) / kBatchLanes;
  const int calling_thread = 0;
  FirstFailure failure;  // the first exception of any window, rethrown after the region

#pragma omp parallel num_threads(std::max(1, options.threads))
  {
    WindowWorkspace workspace;  // reused for every window this thread runs
    const auto& simulations = workspace.simulations;
    const auto& evaluations = workspace.evaluations;
#pragma omp for schedule(dynamic, 1)
    for (long w = 0; w < window_count; ++w) {
      if (options.stop && options.stop->load()) continue;
      failure.run([&] {
        const long first = w * kBatchLanes;
        const auto size = static_cast<std::size_t>(std::min<long>(kBatchLanes, count - first));
        const long* window = todo.data() + first;  // the flat indices of its points
        evaluate_window(points, std::span(window, size), workspace);

        std::optional<StudyResults> snapshot;
        std::optional<SweepProgress> progress;
        {
          std::lock_guard lock(results_mutex);
          for (std::size_t k = 0; k < size; ++k) {
            store_point(results, points, window[k], simulations[k], evaluations[k]);
            ++done;
            if (evaluations[k].summary.status != RunStatus::ok) ++unstable;
          }
          if (omp_get_thread_num() == calling_thread) {
            if (options.checkpoint &&
                seconds_since(last_checkpoint) >= options.checkpoint_seconds) {
              snapshot = results;
              last_checkpoint = Clock::now();
            }
            if (options.progress && seconds_since(last_progress) >= options.progress_seconds) {
              progress = SweepProgress{done, count, unstable, seconds_since(start)};
              last_progress = Clock::now();
            }
          }
        }
        // Slow work (file writing, terminal output) outside the lock.
        if (snapshot) options.checkpoint(*snapshot);
        if (progress) options.progress(*progress);
      });
    }
  }
  // A failed checkpoint (a full disk, a read-only file system) or run ends the sweep here; the
  // last checkpoint written is intact, so --resume continues from it.
  failure.rethrow_if_failed();
  outcome.computed = done;
  outcome.unstable = unstable;
  outcome.interrupted = done < count;
  outcome.wall_time_s = seconds_since(start);
  if (options.progress) options.progress({done, count, unstable, outcome.wall_time_s});
  return outcome;
}

}  // namespace impactid
