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
// Resume: NLopt asks for the same points in the same order given the same plan, so a resumed
// run replays the recorded evaluations while the requested x matches them bit for bit, and
// computes from the first difference on.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "study/plan/plan.hpp"
#include "study/studies/study_results.hpp"

namespace impactid {

inline constexpr double kPenalty = 1e10;

struct OptimizeOptions {
  double checkpoint_seconds = 10.0;
  std::function<void(const StudyResults&)> checkpoint;
  /// After each evaluation: evaluations so far (replayed ones included), the budget, the
  /// evaluations whose status is not ok, and the best feasible objective (NaN before one).
  std::function<void(long evaluations, long max_evaluations, long unstable, double best)> progress;
  const std::atomic<bool>* stop = nullptr;
  const StudyResults* previous = nullptr;  ///< a file to resume from
};

struct OptimizeOutcome {
  StudyResults results;  ///< the evaluations table, best point as root attributes
  long computed = 0;
  long reused = 0;
  long unstable = 0;
  std::optional<long> best;  ///< index of the best feasible evaluation
  std::string termination;   ///< NLopt's result ("XTOL_REACHED", …) or the exception's
  bool interrupted = false;
};

OptimizeOutcome run_optimization(const Plan& plan, const OptimizeOptions& options);

}  // namespace impactid
