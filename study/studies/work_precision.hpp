// A work–precision study (`kind = "work-precision"` in a plan): every method of a list, at its
// given parameters, on every (elements, courant) pair of the plan's rod, with the wall time of
// each run against its errors ε_p, ε_v (Serfőző & Pere 2022, eq. 18,
// doi:10.1556/606.2022.00599) and its number of spurious peaks. It answers "which method, at
// which mesh and step, is accurate enough within my time budget".
//
// Timing. Each point runs `repeats` times, one after the other, on the calling thread; the
// stored wall time is the minimum. Interference from other processes, the OS and cold caches
// only ever adds time, so the minimum is the best estimate of what the run itself costs (the
// mean and median carry the machine's load). The time is RunSummary::wall_time_s: set-up and
// stepping, the cost of the integrator, without computing the indicators. Points run one at a
// time on one thread: runs sharing cores, caches and memory bandwidth time each other's
// interference. The slowest repeat is stored too, as a visible measure of that noise.
//
// Indicators. The first repeat is evaluate() (study/studies/evaluation.hpp), the function behind
// `impactid simulate`: a point's indicators are bit-identical to `simulate` with the same
// parameters. The repeats are deterministic; a repeat whose status differs from the first is a
// bug (asserted).
//
// Results are a StudyResults table (format impactid-results-1, results/README.md) over three
// dimensions: method (its index; the labels are the root attributes method_label_<i>),
// elements and courant, so `impactid export` and `--resume` work as for a grid.
//
// Thread safety: run_work_precision() uses its own workspace; do not share `results`.
#pragma once

#include <atomic>
#include <functional>
#include <optional>

#include "study/plan/plan.hpp"
#include "study/plan/work_precision_points.hpp"
#include "study/studies/study_results.hpp"
#include "study/studies/sweep.hpp"

namespace impactid {

/// The empty table of a work-precision plan: every point not done, every value NaN; the method
/// labels and `repeats` as root attributes.
StudyResults empty_work_precision_results(const Plan& plan);

struct WorkPrecisionOptions {
  /// Called with a consistent copy of the results at most every checkpoint_seconds (not at the
  /// end: the caller saves the final state).
  double checkpoint_seconds = 10.0;
  std::function<void(const StudyResults&)> checkpoint;
  /// Called after each finished point, at most every progress_seconds.
  double progress_seconds = 0.5;
  std::function<void(const SweepProgress&)> progress;
  /// When set to true (e.g. by a signal handler), no further point is started.
  const std::atomic<bool>* stop = nullptr;
};

/// Runs the points of `results` that are not done yet, in flat order, one at a time on the
/// calling thread. Returns the counts as a sweep does.
SweepOutcome run_work_precision(const Plan& plan, StudyResults& results,
                                const WorkPrecisionOptions& options);

}  // namespace impactid
