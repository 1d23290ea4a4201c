#include "core/run/references.hpp"

#include <utility>

#include "core/run/simulation.hpp"

namespace impactid {

ReferenceRun simulate_for_reference() {
  return [](const AssembledScene& scene, const MethodParams& method, ContactTrace& trace) {
    SimulationWorkspace ws;
    const RunSummary summary = simulate(scene, method, RunOptions{}, ws);
    trace = std::move(ws.trace);
    return summary;
  };
}

SceneReference scene_reference(const Scene& scene, const ReferenceOptions& options) {
  return scene_reference(scene, options, simulate_for_reference());
}

ModelReference model_reference(const ModelScene& scene, const ReferenceOptions& options) {
  return model_reference(scene, options, simulate_for_reference());
}

}  // namespace impactid
