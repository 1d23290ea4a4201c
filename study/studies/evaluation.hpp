// One simulation and its indicators: what `impactid simulate` prints and what every sweep point
// stores. A plan point and `simulate` with the same parameters call this same function, so
// they give identical numbers.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_model.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/run/simulation.hpp"
#include "metrics/episodes.hpp"
#include "metrics/evaluation.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

Evaluation evaluate(const Simulation& simulation, SimulationWorkspace& workspace);

/// The primary contact's episodes of the run evaluate() just made with `workspace`, each beside
/// its reference's (metrics/episodes.hpp): the rod's exact solution, a scene of bodies' or a
/// model's reference as evaluate() left it in the workspace. Empty when the run is not ok or the
/// reference has no samples of the contact. `initial_energy` is the run's (RunSummary).
std::vector<EpisodeComparison> primary_episodes(const Simulation& simulation,
                                                const SimulationWorkspace& workspace,
                                                const RunSummary& summary);

/// What one thread reuses from batch to batch: each kernel's storage, and the reference of the
/// last scene of bodies it evaluated (a sweep over method parameters keeps one scene, whose
/// reference is then computed once per thread).
struct BatchEvaluationWorkspace {
  BatchWorkspace rod;
  ChainBatchWorkspace chain;
  ModelBatchWorkspace model;
  std::optional<SceneReference> reference;
  /// The references of users' models (SimulationWorkspace::model_reference and the earlier ones),
  /// as evaluate() keeps them.
  SimulationWorkspace model_references;
};

/// Whether `next` can join a batch that starts with `first`: the rod's scene through its kernel
/// (core/batch/batched_simulation.hpp: both batchable, the same rod, time step and run options,
/// both single-step methods, both composite schemes or both one explicit method), a scene of bodies
/// through the chain kernel
/// (core/batch/batched_chain.hpp: the same assembled system, time step and run options), a user's
/// model through the model kernel (core/batch/batched_model.hpp: central difference on the same
/// model, each point its own time step).
bool batchable_together(const Simulation& first, const Simulation& next);

/// evaluate() for 1..kBatchLanes simulations at once, each batchable_together with the first:
/// out[k] equals evaluate(simulations[k]) bit for bit, wall_time_s aside (the batch's time
/// divided by its runs).
void evaluate_batch(std::span<const Simulation> simulations, BatchEvaluationWorkspace& workspace,
                    std::span<Evaluation> out);

}  // namespace impactid
