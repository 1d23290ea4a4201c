// The batched kernels' entry points at each level (core/batch/kernel_target.hpp): the same
// functions, compiled once per level into their own namespace, with the per-thread storage of a
// BatchWorkspace (or ChainBatchWorkspace) passed in pieces. core/batch/batch_kernels.cpp calls the
// level that kernel_level() names; nothing else calls these.
//
// Internal to core/.
#pragma once

#include <array>
#include <span>
#include <variant>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "core/common/state.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/method.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/model/rod_scene.hpp"
#include "core/methods/stepper_coefficients.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/sparse_system.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// The kind of step a batch of the rod takes (one per batch: same_batch).
enum class BatchStepKind {
  single_step,   ///< the ImplicitCoefficients family
  composite,     ///< Bathe, ρ∞-Bathe, TR-BDF2
  wilson_theta,  ///< Wilson-θ's extended step
  houbolt,       ///< Houbolt's predictors, then the single step from plain rows
};
inline BatchStepKind batch_step_kind(const MethodParams& method) {
  if (stepped_by<CompositeCoefficients>(method)) return BatchStepKind::composite;
  if (stepped_by<WilsonThetaCoefficients>(method)) return BatchStepKind::wilson_theta;
  if (stepped_by<HouboltCoefficients>(method)) return BatchStepKind::houbolt;
  return BatchStepKind::single_step;
}

/// What a batch of the rod writes into: a BatchWorkspace's storage, lane start states and
/// traces.
struct BatchStorage {
  std::vector<LaneBlock>& blocks;
  std::array<State, kBatchLanes>& starts;
  std::array<ContactTrace, kBatchLanes>& traces;
};

}  // namespace impactid

// One level's entry points: simulate_batch, simulate_explicit_batch, simulate_kr_alpha_batch,
// simulate_chain_batch, multiply_add_lanes and simulate_model_batch of the public headers, for that level's registers.
#define IMPACTID_DECLARE_BATCH_KERNELS(level_namespace)                                            \
  namespace impactid::level_namespace {                                                            \
  void simulate_rod_lanes(std::span<const RodScene> scenes, std::span<const MethodParams> methods, \
                          const RunOptions& options, BatchStorage storage,                         \
                          std::span<RunSummary> summaries);                                        \
  void simulate_explicit_lanes(std::span<const RodScene> scenes,                                   \
                               std::span<const MethodParams> methods, const RunOptions& options,   \
                               BatchStorage storage, std::span<RunSummary> summaries);             \
  void simulate_kr_alpha_lanes(std::span<const RodScene> scenes,                                   \
                               std::span<const MethodParams> methods, const RunOptions& options,   \
                               BatchStorage storage, std::span<RunSummary> summaries);             \
  void simulate_chain_lanes(std::span<const AssembledScene* const> scenes,                         \
                            std::span<const MethodParams> methods, const RunOptions& options,      \
                            std::vector<LaneBlock>& blocks,                                        \
                            std::array<State, kBatchLanes>& starts,                                \
                            std::array<ImplicitIntegrator, kBatchLanes>& integrators,              \
                            std::array<ContactTrace, kBatchLanes>& traces,                         \
                            std::span<RunSummary> summaries);                                      \
  void multiply_add_lanes(const SparseMatrix& a, double s, std::span<const LaneBlock> x,           \
                          std::span<LaneBlock> y);                                                 \
  void simulate_model_lanes(std::span<const AssembledScene* const> scenes,                         \
                            std::span<const MethodParams> methods, const RunOptions& options,      \
                            std::vector<LaneBlock>& blocks,                                        \
                            std::array<State, kBatchLanes>& states,                                \
                            std::array<SparseCentralDifference, kBatchLanes>& steppers,            \
                            std::array<ContactTrace, kBatchLanes>& traces,                         \
                            SimulationWorkspace& scalar, int& kernel_lanes,                        \
                            std::span<RunSummary> summaries);                                      \
  }

IMPACTID_DECLARE_BATCH_KERNELS(kernels_x86_64_v3)
IMPACTID_DECLARE_BATCH_KERNELS(kernels_x86_64_v4)
