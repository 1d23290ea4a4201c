// Several runs of one scene of bodies advanced together, one per SIMD lane: the implicit step
// with a constraint list (ImplicitIntegrator::step_constraints,
// core/methods/implicit_integrator.hpp) for kBatchLanes parameter points at once. The rod's kernel
// (core/batch/batched_simulation.hpp) knows the uniform rod with its wall at the last unknown; this
// one takes any assembled chain (core/model/scene_assembly.hpp): a tridiagonal system whose rows
// change from segment to segment and are uncoupled between bodies, and a list of contacts between
// bodies or with a wall.
//
// Bit-identical to simulate(): every lane performs the scalar step's operations on its own
// numbers, in the same order, with the same fused multiply-adds (the project builds with
// -ffp-contract=off), and the scalar step's per-lane branches become blends. Each lane's
// factorisation, constraint columns and Delassus matrix are the scalar integrator's own
// (ImplicitIntegrator::initialize, run once per lane), interleaved [unknown][lane]; the contact
// problem of a step is solved per lane by the same solver (core/algebra/contact_lcp.hpp), and only
// in the lanes where some contact would penetrate (elsewhere its answer is zero, which the kernel
// then uses without calling it). So a lane's RunSummary and trace equal simulate()'s bit for bit
// (tests/batched_chain_test.cpp), whatever the other lanes do.
//
// As in the rod's kernel, the update u = u* + b1·Δt²·a, v = v* + g1·Δt·a of a row is deferred to
// the next step's forward sweep (the same operations, so the same bits), except in the first and
// the last row: a wall's node is one of them, and its displacement is put exactly on the wall at
// the end of the step.
//
// What batches (chain_batchable / same_chain_batch): implicit methods on a scene with a
// constraint list (scenes of bodies, three or more nodes) whose bodies start free and unstrained
// (no clamped end, no initial displacement, no gravity: those run through simulate()), no
// histories; lanes of one batch share the assembled matrices, the contacts' nodes and probes, the
// time step and the run options, and may differ in the method and its parameters, the gaps, the
// initial velocities, the first contact time, the primary contact and the end time.
//
// Thread safety: one ChainBatchWorkspace per thread; simulate_chain_batch is reentrant.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/method.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// Whether a run can go through simulate_chain_batch: an implicit method, an assembled scene
/// with a constraint list whose walls hold the first or the last node, whose bodies start free
/// and unstrained (AssembledScene::starts_free: no clamped end, no initial displacement), no
/// histories.
bool chain_batchable(const AssembledScene& scene, const MethodParams& method,
                     const RunOptions& options);

/// Whether two chain_batchable runs can share a batch: the same matrices, contact nodes,
/// probes, time step and free-flight rule, the same run options.
bool same_chain_batch(const AssembledScene& a, const RunOptions& options_a, const AssembledScene& b,
                      const RunOptions& options_b);

/// Per-thread storage reused from batch to batch (allocation-free once sized).
class ChainBatchWorkspace {
 public:
  /// Lane k's trace after simulate_chain_batch, as simulate() leaves it in
  /// SimulationWorkspace::trace.
  std::array<ContactTrace, kBatchLanes> traces;

 private:
  friend void simulate_chain_batch(std::span<const AssembledScene* const>,
                                   std::span<const MethodParams>, const RunOptions&,
                                   ChainBatchWorkspace&, std::span<RunSummary>);
  std::vector<LaneBlock> storage_;        // the interleaved [unknown][lane] arrays
  std::array<State, kBatchLanes> start_;  // each lane's state when it starts stepping
  std::array<ImplicitIntegrator, kBatchLanes> integrators_;  // each lane's set-up
  SimulationWorkspace scalar_;  // the baseline level's runs, one at a time
};

/// Runs *scenes[k] with methods[k] for k < scenes.size() (1..kBatchLanes runs, each
/// chain_batchable and same_chain_batch with the first; methods valid) and writes summaries[k]
/// and workspace.traces[k]: the same numbers simulate() gives for that run. wall_time_s is the
/// batch's time divided by the number of runs in it.
void simulate_chain_batch(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          ChainBatchWorkspace& workspace, std::span<RunSummary> summaries);

}  // namespace impactid
