// `optimize` studies: NLopt (2.7) over bounded continuous parameters, minimising a weighted sum
// of indicators subject to inequality constraints on indicators. Every evaluation is recorded
// (the evaluations table: dimension "evaluation"); the best feasible evaluation is reported,
// whatever NLopt itself returns or throws (roundoff_limited and forced_stop still leave a
// usable best point).
//
// Conventions: a run that is not ok (unstable, failed) or whose objective indicators are NaN
// scores kPenalty and violates every constraint by kPenalty, so the optimiser is pushed away
// without seeing a NaN. Algorithms without native inequality constraints (all but COBYLA,
// ISRES and the ORIG_DIRECT variants) are wrapped in NLopt's AUGLAG when the plan has
// constraints. Stochastic algorithms are seeded (plan key `seed`), so a plan repeats.
//
// Several starts (plan key `starts`, default 1): independent searches, the one parallelism an
// NLopt search can use (docs/scale.md). Each local search chooses its next point from the
// previous ones, and NLopt's population methods call the objective one point at a time, so
// neither can be spread over threads; separate searches can, and on these non-convex surfaces
// more starts are what guards against a local optimum. Search 0 starts at the parameters'
// `start` (a one-search plan is exactly the plain optimisation), search k >= 1 at the k-th
// point of the Halton sequence (bases 2, 3, 5, …) scaled to the bounds, with NLopt's generator
// seeded with seed + k. Every search has its own budget of max_evaluations. The searches run
// on the OpenMP threads, or over MPI ranks through OptimizeOptions::searches. The table lists
// each search's evaluations in order, search after search, with a column `start` when there
// are several; the best is the first evaluation with the least objective among the feasible
// ones. So the file does not depend on the number of threads or ranks.
//
// Resume: NLopt asks for the same points in the same order given the same plan, so a resumed
// search replays its recorded evaluations while the requested x matches them bit for bit, and
// computes from the first difference on.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "study/plan/plan.hpp"
#include "study/studies/study_results.hpp"

namespace impactid {

inline constexpr double kPenalty = 1e10;

/// One search's end: its evaluations (the table's columns without `start` and without
/// attributes), NLopt's result ("XTOL_REACHED", …, or the exception's) and its counts.
struct SearchOutcome {
  StudyResults rows;
  std::string termination;
  long computed = 0;
  long reused = 0;
  bool interrupted = false;
};

/// Runs searches [each index of `starts`] to their ends, each replaying previous[index]'s rows
/// (that search's evaluations of an earlier run, possibly none), and hands every outcome to
/// `done` as it ends (from the calling thread). Stops early when `stop` is set.
using SearchRunner = std::function<void(
    const Plan& plan, std::span<const long> starts, std::span<const StudyResults> previous,
    const std::atomic<bool>* stop, const std::function<void(long start, SearchOutcome)>& done)>;

struct OptimizeOptions {
  int threads = 1;  ///< searches run at once (a single search is serial)
  double checkpoint_seconds = 10.0;
  std::function<void(const StudyResults&)> checkpoint;
  /// After each evaluation: evaluations so far (replayed ones included), the budget (starts ×
  /// max_evaluations), the evaluations whose status is not ok, and the best feasible objective
  /// (NaN before one). Under `searches`, after each search instead.
  std::function<void(long evaluations, long max_evaluations, long unstable, double best)> progress;
  const std::atomic<bool>* stop = nullptr;
  const StudyResults* previous = nullptr;  ///< a file to resume from
  /// Runs the searches elsewhere (the MPI ranks, study/cli/mpi_search.cpp); unset: on
  /// `threads` OpenMP threads.
  SearchRunner searches;
};

struct OptimizeOutcome {
  StudyResults results;  ///< the evaluations table, best point as root attributes
  long computed = 0;
  long reused = 0;
  long unstable = 0;
  std::optional<long> best;  ///< index of the best feasible evaluation
  std::string termination;   ///< NLopt's result, "start k: …; …" for several searches
  bool interrupted = false;
};

OptimizeOutcome run_optimization(const Plan& plan, const OptimizeOptions& options);

/// Search `start`'s first point (see the header comment).
std::vector<double> start_point(const OptimizeStudy& study, long start);

/// Runs search `start` alone, replaying `previous` (its rows of an earlier run, or null).
SearchOutcome run_search(const Plan& plan, long start, const StudyResults* previous,
                         const std::atomic<bool>* stop);

/// The evaluations table of `plan` with no rows: the columns every search fills.
StudyResults empty_search_rows(const Plan& plan);

}  // namespace impactid
