#include "study/studies/evaluation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <variant>
#include <vector>

#include "core/model/scene_assembly.hpp"
#include "core/reference/exact_solution.hpp"
#include "core/run/references.hpp"

namespace impactid {

namespace {

// The indicators of a run of a scene of bodies against the scene's reference, which `reference`
// caches from run to run.
Evaluation evaluate_bodies(const Simulation& sim, const Scene& bodies,
                           const AssembledScene& scene, const RunSummary& summary,
                           const ContactTrace& trace, std::optional<SceneReference>& reference) {
  Evaluation out;
  out.summary = summary;
  const ReferenceOptions options = reference_options(sim);
  if (!reference || reference->scene != bodies || reference->options != options) {
    reference = scene_reference(bodies, options);
  }
  out.contacts.resize(scene.probes.size());
  if (!reference->usable() && out.summary.status == RunStatus::ok) {
    // Nothing to measure the run against: its indicators are not results.
    out.summary.status = RunStatus::failed;
    out.summary.message = "no reference for the scene: " + reference->message;
  }
  out.indicators =
      evaluate_indicators(bodies, *reference, trace, out.summary, sim.indicators, out.contacts);
  out.reference_refinements = reference->refinements;
  out.reference_change = reference->change;
  out.reference = reference->description();
  out.reference_trusted = reference->converged;
  out.reference_error = reference->refinements == 0 ? 0.0 : reference->change;
  out.verdict = judge(out.summary.status, out.indicators, out.reference_trusted, sim.verdict);
  return out;
}

// A run of a user's model measured against its reference, which the workspace caches from run to
// run (SimulationWorkspace::model_reference and the earlier ones).
Evaluation measure_model(const Simulation& sim, const ModelScene& scene, const RunSummary& summary,
                         const ContactTrace& trace, SimulationWorkspace& workspace) {
  Evaluation out;
  out.summary = summary;
  const ReferenceOptions options = reference_options(sim);
  std::optional<ModelReference>& reference = workspace.model_reference;
  if (!reference || !(reference->scene == scene) || !(reference->options == options)) {
    // One computed earlier by this workspace, else a new one; the last one goes to the earlier.
    std::vector<ModelReference>& earlier = workspace.earlier_model_references;
    const auto found = std::find_if(earlier.begin(), earlier.end(), [&](const ModelReference& r) {
      return r.scene == scene && r.options == options;
    });
    std::optional<ModelReference> next;
    if (found != earlier.end()) {
      next = std::move(*found);
      earlier.erase(found);
    } else {
      next = model_reference(scene, options);
    }
    if (reference) {
      if (earlier.size() == SimulationWorkspace::kEarlierModelReferences) {
        earlier.erase(earlier.begin());
      }
      earlier.push_back(std::move(*reference));
    }
    reference = std::move(next);
  }
  const int primary = primary_contact_index(scene);
  out.contacts.resize(scene.model->contacts.size());
  if (!reference->usable(primary) && out.summary.status == RunStatus::ok) {
    out.summary.status = RunStatus::failed;
    out.summary.message = "no reference for the model: " + reference->message;
  }
  std::vector<ContactSamples> samples = reference->contacts;
  samples.resize(out.contacts.size());
  out.indicators =
      evaluate_indicators(samples, primary, trace, out.summary, sim.indicators, out.contacts);
  out.reference_refinements = reference->refinements;
  out.reference_change = reference->change;
  out.reference_dt = reference->dt;
  out.reference = reference->description();
  out.reference_trusted = reference->trusted();
  out.reference_error = reference->error;
  out.verdict = judge(out.summary.status, out.indicators, out.reference_trusted, sim.verdict);
  return out;
}

Evaluation evaluate_model(const Simulation& sim, const ModelScene& scene,
                          SimulationWorkspace& workspace) {
  const RunSummary summary = simulate(assemble(scene), sim.method, sim.run, workspace);
  return measure_model(sim, scene, summary, workspace.trace, workspace);
}

// A batch's scenes assembled (by `assemble_one`, of each simulation) and its methods, as the
// kernels take them.
class AssembledBatch {
 public:
  template <class Assemble>
  AssembledBatch(std::span<const Simulation> simulations, Assemble&& assemble_one)
      : count_(simulations.size()) {
    scenes_.reserve(count_);
    for (std::size_t k = 0; k < count_; ++k) {
      scenes_.push_back(assemble_one(simulations[k]));
      pointers_[k] = &scenes_.back();
      methods_[k] = simulations[k].method;
    }
  }
  std::span<const AssembledScene* const> scenes() const {
    return std::span(pointers_).first(count_);
  }
  std::span<const MethodParams> methods() const { return std::span(methods_).first(count_); }
  const AssembledScene& operator[](std::size_t k) const { return scenes_[k]; }
  AssembledBatch(const AssembledBatch&) = delete;  // pointers_ point into scenes_
  AssembledBatch& operator=(const AssembledBatch&) = delete;

 private:
  std::size_t count_;
  std::vector<AssembledScene> scenes_;
  std::array<const AssembledScene*, kBatchLanes> pointers_{};
  std::array<MethodParams, kBatchLanes> methods_;
};

// evaluate_batch of a user's model: one run of the model kernel, then each lane's indicators.
void evaluate_models_batch(std::span<const Simulation> simulations,
                           BatchEvaluationWorkspace& workspace, std::span<Evaluation> out) {
  const std::size_t count = simulations.size();
  AssembledBatch batch(simulations, [](const Simulation& s) { return assemble(*s.model()); });
  std::array<RunSummary, kBatchLanes> summaries;
  simulate_model_batch(batch.scenes(), batch.methods(), simulations[0].run, workspace.model,
                       std::span(summaries).first(count));
  for (std::size_t k = 0; k < count; ++k) {
    out[k] = measure_model(simulations[k], *simulations[k].model(), summaries[k],
                           workspace.model.traces[k], workspace.model_references);
  }
}

// evaluate_batch of scenes of bodies: one run of the chain kernel, then each lane's indicators.
void evaluate_bodies_batch(std::span<const Simulation> simulations,
                           BatchEvaluationWorkspace& workspace, std::span<Evaluation> out) {
  const std::size_t count = simulations.size();
  AssembledBatch batch(simulations, [](const Simulation& s) { return assemble(*s.bodies()); });
  std::array<RunSummary, kBatchLanes> summaries;
  std::array<ContactTrace, kBatchLanes>* traces = &workspace.chain.traces;
  if (as_rod(*simulations[0].bodies())) {
    // The paper's form (batchable_together): the rod's kernel, whose trace then gets the one
    // contact's columns as simulate() gives them.
    std::array<RodScene, kBatchLanes> rods;
    for (std::size_t k = 0; k < count; ++k) rods[k] = *as_rod(*simulations[k].bodies());
    simulate_batch(std::span(rods).first(count), batch.methods(), simulations[0].run,
                   workspace.rod, std::span(summaries).first(count));
    traces = &workspace.rod.traces;
    for (std::size_t k = 0; k < count; ++k) {
      ContactTrace& trace = workspace.rod.traces[k];
      trace.contact_pressure.assign(1, trace.pressure);
      trace.contact_velocity.assign(1, trace.velocity);
    }
  } else {
    simulate_chain_batch(batch.scenes(), batch.methods(), simulations[0].run, workspace.chain,
                         std::span(summaries).first(count));
  }
  for (std::size_t k = 0; k < count; ++k) {
    out[k] = evaluate_bodies(simulations[k], *simulations[k].bodies(), batch[k], summaries[k],
                             (*traces)[k], workspace.reference);
  }
}

}  // namespace

Evaluation evaluate(const Simulation& sim, SimulationWorkspace& workspace) {
  return std::visit(
      Overloaded{[&](const RodScene& rod) {
                   Evaluation out;
                   out.summary = simulate(rod, sim.method, sim.run, workspace);
                   out.indicators =
                       evaluate_indicators(rod, workspace.trace, out.summary, sim.indicators);
                   out.verdict = judge(out.summary.status, out.indicators, true, sim.verdict);
                   return out;
                 },
                 [&](const Scene& bodies) {
                   const AssembledScene scene = assemble(bodies);
                   const RunSummary summary = simulate(scene, sim.method, sim.run, workspace);
                   return evaluate_bodies(sim, bodies, scene, summary, workspace.trace,
                                          workspace.reference);
                 },
                 [&](const ModelScene& model) { return evaluate_model(sim, model, workspace); }},
      sim.scene);
}

std::vector<EpisodeComparison> primary_episodes(const Simulation& sim,
                                                const SimulationWorkspace& workspace,
                                                const RunSummary& summary) {
  if (summary.status != RunStatus::ok) return {};
  const ContactTrace& trace = workspace.trace;
  // The primary contact's reference pressure at the samples and its pressure scale, as the
  // indicators take them (metrics/indicators.cpp).
  std::vector<double> reference;
  double scale = 0.0;
  std::visit(
      Overloaded{[&](const RodScene& rod) {
                   const RodImpactExact exact(rod);
                   for (long i = 0; i < trace.size(); ++i) {
                     reference.push_back(exact.at_sample(i + 1).pressure);
                   }
                   scale = derive(rod).pressure_scale;
                 },
                 [&](const Scene& bodies) {
                   const SceneDerived derived = derive(bodies);
                   const auto primary = static_cast<std::size_t>(derived.primary_contact);
                   if (!workspace.reference || !workspace.reference->usable()) return;
                   reference = workspace.reference->contacts[primary].pressure;
                   scale = contact_pressure_scale(bodies, scene_contacts(bodies)[primary],
                                                  derived.velocity_scale);
                 },
                 [&](const ModelScene& model) {
                   const auto primary = static_cast<std::size_t>(primary_contact_index(model));
                   if (!workspace.model_reference ||
                       primary >= workspace.model_reference->contacts.size()) {
                     return;
                   }
                   reference = workspace.model_reference->contacts[primary].pressure;
                   for (const double p : reference) scale = std::max(scale, std::abs(p));
                 }},
      sim.scene);
  if (reference.size() != trace.pressure.size()) return {};
  return compare_episodes(reference, trace.pressure, summary.dt,
                          sim.indicators.peak_prominence * scale, trace.energy,
                          summary.initial_energy);
}

bool batchable_together(const Simulation& first, const Simulation& next) {
  const auto rods = [&](const RodScene& a, const RodScene& b) {
    return batchable(a, first.method, first.run) && batchable(b, next.method, next.run) &&
           same_batch(a, first.method, first.run, b, next.method, next.run);
  };
  return std::visit(
      Overloaded{
          rods,
          [&](const Scene& a_bodies, const Scene& b_bodies) {
            // The paper's form runs on the rod's named contact: the rod's kernel takes it.
            const std::optional<RodScene> rod_a = as_rod(a_bodies), rod_b = as_rod(b_bodies);
            if (rod_a || rod_b) return rod_a && rod_b && rods(*rod_a, *rod_b);
            const AssembledScene a = assemble(a_bodies), b = assemble(b_bodies);
            return chain_batchable(a, first.method, first.run) &&
                   chain_batchable(b, next.method, next.run) &&
                   same_chain_batch(a, first.run, b, next.run);
          },
          [&](const ModelScene& a_model, const ModelScene& b_model) {
            // The cheap tests first: assembling copies the model's matrices.
            if (a_model.model != b_model.model || !model_kernel_method(first.method) ||
                !model_kernel_method(next.method)) {
              return false;
            }
            const AssembledScene a = assemble(a_model), b = assemble(b_model);
            return model_batchable(a, first.method, first.run) &&
                   model_batchable(b, next.method, next.run) &&
                   same_model_batch(a, first.run, b, next.run);
          },
          // Scenes of different kinds never share a batch.
          [](const auto&, const auto&) { return false; }},
      first.scene, next.scene);
}

void evaluate_batch(std::span<const Simulation> simulations, BatchEvaluationWorkspace& workspace,
                    std::span<Evaluation> out) {
  if (simulations[0].bodies()) {
    evaluate_bodies_batch(simulations, workspace, out);
    return;
  }
  if (simulations[0].model()) {
    evaluate_models_batch(simulations, workspace, out);
    return;
  }
  std::array<RodScene, kBatchLanes> scenes;
  std::array<MethodParams, kBatchLanes> methods;
  std::array<RunSummary, kBatchLanes> summaries;
  const std::size_t count = simulations.size();
  for (std::size_t k = 0; k < count; ++k) {
    scenes[k] = *simulations[k].rod();
    methods[k] = simulations[k].method;
  }
  simulate_batch(std::span(scenes).first(count), std::span(methods).first(count),
                 simulations[0].run, workspace.rod, std::span(summaries).first(count));
  // Consecutive lanes of one scene (in a sweep over method parameters, all of them) share the
  // exact solution: their indicators are evaluated together.
  std::array<const ContactTrace*, kBatchLanes> traces;
  std::array<IndicatorOptions, kBatchLanes> options;
  std::array<Indicators, kBatchLanes> indicators;
  for (std::size_t k = 0; k < count; ++k) {
    out[k].summary = summaries[k];
    traces[k] = &workspace.rod.traces[k];
    options[k] = simulations[k].indicators;
  }
  for (std::size_t begin = 0, end = 0; begin < count; begin = end) {
    end = begin + 1;
    while (end < count && scenes[end] == scenes[begin]) ++end;
    const std::size_t n = end - begin;
    evaluate_indicators(scenes[begin], std::span(traces).subspan(begin, n),
                        std::span(summaries).subspan(begin, n),
                        std::span(options).subspan(begin, n),
                        std::span(indicators).subspan(begin, n));
  }
  for (std::size_t k = 0; k < count; ++k) {
    out[k].indicators = indicators[k];
    out[k].verdict = judge(summaries[k].status, indicators[k], true, simulations[k].verdict);
  }
}

}  // namespace impactid
