// Several runs of one user's model advanced together, one per SIMD lane: central difference on a
// sparse model (SparseCentralDifference, core/methods/sparse_integrators.hpp) for kBatchLanes
// points at once, the lanes on sparse systems of issue 37. A point alone reads the whole
// stiffness matrix once per step for one vector; here each stored entry is read once for every
// lane (core/batch/sparse_lanes.hpp), and the rest of the step is O(n) per lane in SIMD.
//
// Bit-identical to simulate(): each lane's set-up is the scalar stepper's own
// (SparseCentralDifference::initialize and its first step, run once per lane), and each step
// repeats that stepper's operations in the same order on the lane's numbers: the predictor, the
// products with M and K (the scalar's skip of a zero column as a blend), the diagonal solve, the
// contact violations, the O(m) answer of a diagonal Delassus matrix
// (core/algebra/contact_lcp.hpp: solve_diagonal_contact_lcp), the correction, the walls put
// exactly on their gap, the central velocity and the method's own energy at the check samples.
// So a lane's RunSummary and trace equal simulate()'s bit for bit (tests/batched_model_test.cpp),
// whatever the other lanes do.
//
// What batches (model_batchable / same_model_batch): central difference with the central velocity
// on a sparse model without damping, Lagrange multipliers, no histories. The lanes of one batch
// share the model's matrices, contacts and probes and the run options, and may differ in the time
// step (a Courant sweep, the explicit sweep a model needs) and the end time. A lane the kernel
// cannot take once its stepper is set up (a mass or a Delassus matrix that is not diagonal, a
// step above the explicit limit, whose energy is the plain one) runs through simulate() in the
// same call, so a caller may batch by the cheap test alone.
//
// Thread safety: one ModelBatchWorkspace per thread; simulate_model_batch is reentrant.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "core/methods/method.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// Whether the model kernel steps this method: central difference with the central velocity. The
/// cheap part of model_batchable, for callers that would otherwise assemble a model to learn it.
bool model_kernel_method(const MethodParams& method);

/// Whether a run can go through simulate_model_batch: a sparse model (AssembledScene::sparse)
/// without damping, with contacts; central difference with the central velocity; Lagrange
/// multipliers; no histories.
bool model_batchable(const AssembledScene& scene, const MethodParams& method,
                     const RunOptions& options);

/// Whether two model_batchable runs can share a batch: the same matrices (the same stored
/// entries, bit for bit), contacts, probes and initial state, the same run options.
bool same_model_batch(const AssembledScene& a, const RunOptions& options_a, const AssembledScene& b,
                      const RunOptions& options_b);

/// Per-thread storage reused from batch to batch.
class ModelBatchWorkspace {
 public:
  /// Lane k's trace after simulate_model_batch, as simulate() leaves it in
  /// SimulationWorkspace::trace.
  std::array<ContactTrace, kBatchLanes> traces;
  /// How many of the last batch's runs the kernel stepped (the others went through simulate():
  /// none on baseline x86-64).
  int kernel_lanes() const { return kernel_lanes_; }

 private:
  friend void simulate_model_batch(std::span<const AssembledScene* const>,
                                   std::span<const MethodParams>, const RunOptions&,
                                   ModelBatchWorkspace&, std::span<RunSummary>);
  std::vector<LaneBlock> storage_;                             // [unknown][lane] arrays
  std::array<State, kBatchLanes> states_;                      // each lane's state at its start
  std::array<SparseCentralDifference, kBatchLanes> steppers_;  // each lane's set-up
  SimulationWorkspace scalar_;  // the lanes the kernel does not take, and the baseline level's
  int kernel_lanes_ = 0;
};

/// Runs *scenes[k] with methods[k] for k < scenes.size() (1..kBatchLanes runs, each
/// model_batchable and same_model_batch with the first; methods valid) and writes summaries[k]
/// and workspace.traces[k]: the same numbers simulate() gives for that run. wall_time_s is the
/// kernel's time divided by the number of runs it took (a lane run through simulate() keeps its
/// own).
void simulate_model_batch(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          ModelBatchWorkspace& workspace, std::span<RunSummary> summaries);

}  // namespace impactid
