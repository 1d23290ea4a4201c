// Running the points of a grid or list plan in parallel (OpenMP, dynamic scheduling), one
// SimulationWorkspace per thread. Scheduling is kept apart from simulation and writing: the
// driver takes a list of flat point indices and fills a StudyResults table; what to run (all
// points, the ones a resumed file lacks, a shard for another process) and where to save it are
// the caller's choice.
//
// A thread takes the points kBatchLanes at a time (a window, its unit of work), builds them and
// runs them: consecutive points of the window that can share a batch (implicit methods, central
// difference, Noh–Bathe or Kim's scheme on the same single-wall rod and time step, no histories:
// study/studies/evaluation.hpp) run together through the SIMD kernels of
// core/batch/batched_simulation.hpp, and each point of a batch reports the
// batch's wall time divided by its points.
//
// Determinism: a point's numbers depend only on its index (the batched kernel gives simulate()'s
// numbers bit for bit), so any thread count and any interruption give bit-identical results
// (wall_time_s aside).
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <span>
#include <vector>

#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/evaluation.hpp"
#include "study/studies/study_results.hpp"

namespace impactid {

struct SweepProgress {
  long done = 0;      ///< points finished in this run
  long total = 0;     ///< points to compute in this run
  long unstable = 0;  ///< finished points whose status is not ok
  double elapsed_s = 0;
};

struct SweepOptions {
  int threads = 1;  ///< >= 1
  /// Called on the calling thread with a consistent copy of the results at most every
  /// checkpoint_seconds (and not at the end: the caller saves the final state).
  double checkpoint_seconds = 10.0;
  std::function<void(const StudyResults&)> checkpoint;
  /// Called on the calling thread after each finished point, at most every progress_seconds.
  double progress_seconds = 0.5;
  std::function<void(const SweepProgress&)> progress;
  /// When set to true (e.g. by a signal handler), no further point is started.
  const std::atomic<bool>* stop = nullptr;
};

struct SweepOutcome {
  long computed = 0;  ///< points computed in this run
  long reused = 0;    ///< points already done (from a resumed file)
  long unstable = 0;  ///< computed points whose status is not ok
  bool interrupted = false;
  double wall_time_s = 0;
};

/// The empty table of a grid or list plan: every point not done, every value NaN.
StudyResults empty_results(const Plan& plan, const PointSet& points);
/// The same columns with `rows` rows rather than one per point: a buffer for some of the points
/// (an MPI worker's batch, study/cli/mpi_sweep.hpp), filled by store_point_row.
StudyResults empty_results(const Plan& plan, const PointSet& points, std::size_t rows);

/// The columns and attributes that record a scene's reference at every point (a scene of bodies'
/// or a model's: reference_refinements, reference_change, and for a model reference_dt and the
/// model_* attributes); nothing for the rod. Shared with the work-precision study.
void add_reference_columns(const SimulationSettings& base, std::size_t size, StudyResults& r);
/// Stores point i's reference into those columns.
void store_reference_columns(StudyResults& results, std::size_t i, const Evaluation& evaluation);

/// Adds the verdict column (kVerdictColumn) and its attribute. Shared with the work-precision
/// study.
void add_verdict_column(const SimulationSettings& base, std::size_t size, StudyResults& r);
/// Stores point i's verdict into that column (nothing when the table has none: a file of an
/// impactid without verdicts, resumed).
void store_verdict(StudyResults& results, std::size_t i, const Evaluation& evaluation);

/// "12 accurate, 3 oscillating, 1 unverified": how many done points have each verdict, in order
/// of severity, those with none left out; "" when the table has no verdict column.
std::string verdict_summary(const StudyResults& results);

/// Stores one evaluated point (status, varied parameters, β, γ, indicators) at `index`.
void store_point(StudyResults& results, const PointSet& points, long index,
                 const Simulation& simulation, const Evaluation& evaluation);
/// The same into row `row` of a table of fewer rows than points (empty_results with rows).
void store_point_row(StudyResults& results, std::size_t row, const PointSet& points, long index,
                     const Simulation& simulation, const Evaluation& evaluation);

/// What one thread needs to run windows of points, reused from window to window.
struct WindowWorkspace {
  SimulationWorkspace single;  ///< a point run on its own
  BatchEvaluationWorkspace batch;
  std::array<Simulation, kBatchLanes> simulations;
  std::array<Evaluation, kBatchLanes> evaluations;
};

/// Builds and runs up to kBatchLanes points (their flat indices), batching consecutive points
/// that can share a batch, into workspace.simulations[k] and workspace.evaluations[k]: the
/// sweep's unit of work, shared by every way of scheduling it (threads, MPI ranks).
void evaluate_window(const PointSet& points, std::span<const long> window,
                     WindowWorkspace& workspace);

/// Those of `indices` that `results` does not have yet, in order; `reused` counts the others.
std::vector<long> points_to_compute(std::span<const long> indices, const StudyResults& results,
                                    long& reused);

/// Computes those of `indices` that `results` does not have yet.
SweepOutcome run_sweep(const PointSet& points, std::span<const long> indices, StudyResults& results,
                       const SweepOptions& options);

}  // namespace impactid
