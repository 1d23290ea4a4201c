#include "study/evaluation.hpp"

namespace impactid {

Evaluation evaluate(const Simulation& sim, SimulationWorkspace& workspace) {
  Evaluation out;
  out.summary = simulate(sim.scene, sim.method, sim.run, workspace);
  out.indicators = evaluate_indicators(sim.scene, workspace.trace, out.summary, sim.indicators);
  return out;
}

}  // namespace impactid
