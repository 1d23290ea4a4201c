#include "study/evaluation.hpp"

namespace impactid {

Evaluation evaluate(const Simulation& sim, SimulationWorkspace& workspace) {
  Evaluation out;
  out.summary = simulate(sim.scene, sim.method, sim.run, workspace);
  out.indicators = evaluate_indicators(sim.scene, workspace.trace, out.summary, sim.indicators);
  return out;
}

bool batchable_together(const Simulation& first, const Simulation& next) {
  return batchable(first.scene, first.method, first.run) &&
         batchable(next.scene, next.method, next.run) &&
         same_batch(first.scene, first.run, next.scene, next.run);
}

void evaluate_batch(std::span<const Simulation> simulations, BatchWorkspace& workspace,
                    std::span<Evaluation> out) {
  std::array<RodScene, kBatchLanes> scenes;
  std::array<MethodParams, kBatchLanes> methods;
  std::array<RunSummary, kBatchLanes> summaries;
  const std::size_t count = simulations.size();
  for (std::size_t k = 0; k < count; ++k) {
    scenes[k] = simulations[k].scene;
    methods[k] = simulations[k].method;
  }
  simulate_batch(std::span(scenes).first(count), std::span(methods).first(count),
                 simulations[0].run, workspace, std::span(summaries).first(count));
  for (std::size_t k = 0; k < count; ++k) {
    out[k].summary = summaries[k];
    out[k].indicators = evaluate_indicators(simulations[k].scene, workspace.traces[k],
                                            summaries[k], simulations[k].indicators);
  }
}

}  // namespace impactid
