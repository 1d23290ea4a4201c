#include "study/evaluation.hpp"

#include <array>

#include "core/scene_assembly.hpp"

namespace impactid {

Evaluation evaluate(const Simulation& sim, SimulationWorkspace& workspace) {
  Evaluation out;
  if (sim.bodies) {
    const AssembledScene scene = assemble(*sim.bodies);
    out.summary = simulate(scene, sim.method, sim.run, workspace);
    const ReferenceOptions options{.tolerance = sim.indicators.reference_tolerance};
    if (!workspace.reference || workspace.reference->scene != *sim.bodies ||
        workspace.reference->options != options) {
      workspace.reference = scene_reference(*sim.bodies, options);
    }
    out.contacts.resize(scene.probes.size());
    if (!workspace.reference->usable() && out.summary.status == RunStatus::ok) {
      // Nothing to measure the run against: its indicators are not results.
      out.summary.status = RunStatus::failed;
      out.summary.message = "no reference for the scene: " + workspace.reference->message;
    }
    out.indicators = evaluate_indicators(*sim.bodies, *workspace.reference, workspace.trace,
                                         out.summary, sim.indicators, out.contacts);
    out.reference_refinements = workspace.reference->refinements;
    out.reference_change = workspace.reference->change;
    return out;
  }
  out.summary = simulate(sim.scene, sim.method, sim.run, workspace);
  out.indicators = evaluate_indicators(sim.scene, workspace.trace, out.summary, sim.indicators);
  return out;
}

bool batchable_together(const Simulation& first, const Simulation& next) {
  // The batched kernel knows the rod's scene only; scenes of bodies run one by one.
  if (first.bodies || next.bodies) return false;
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
  // Consecutive lanes of one scene (in a sweep over method parameters, all of them) share the
  // exact solution: their indicators are evaluated together.
  std::array<const ContactTrace*, kBatchLanes> traces;
  std::array<IndicatorOptions, kBatchLanes> options;
  std::array<Indicators, kBatchLanes> indicators;
  for (std::size_t k = 0; k < count; ++k) {
    out[k].summary = summaries[k];
    traces[k] = &workspace.traces[k];
    options[k] = simulations[k].indicators;
  }
  for (std::size_t begin = 0, end = 0; begin < count; begin = end) {
    end = begin + 1;
    while (end < count && simulations[end].scene == simulations[begin].scene) ++end;
    const std::size_t n = end - begin;
    evaluate_indicators(simulations[begin].scene, std::span(traces).subspan(begin, n),
                        std::span(summaries).subspan(begin, n),
                        std::span(options).subspan(begin, n),
                        std::span(indicators).subspan(begin, n));
  }
  for (std::size_t k = 0; k < count; ++k) out[k].indicators = indicators[k];
}

}  // namespace impactid
