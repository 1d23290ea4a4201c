// The public entry points of the batched kernels: each calls the level kernel_level() names
// (core/common/kernel_level.hpp) through its row of the kernel table. On baseline x86-64 no kernel
// is compiled: each run goes through simulate(), which gives the numbers the kernels give.
#include "core/batch/batch_kernels.hpp"

#include <type_traits>
#include <utility>

#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/batch/batched_kr_alpha.hpp"
#include "core/batch/batched_model.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/batch/sparse_lanes.hpp"
#include "core/common/kernel_level.hpp"

namespace impactid {
namespace {

// One level's entry points (core/batch/batch_kernels.hpp).
struct LevelKernels {
  decltype(&kernels_x86_64_v4::simulate_rod_lanes) rod;
  decltype(&kernels_x86_64_v4::simulate_explicit_lanes) explicit_methods;
  decltype(&kernels_x86_64_v4::simulate_kr_alpha_lanes) kr_alpha;
  decltype(&kernels_x86_64_v4::simulate_chain_lanes) chain;
  decltype(&kernels_x86_64_v4::multiply_add_lanes) sparse_product;
  decltype(&kernels_x86_64_v4::simulate_model_lanes) model;
};
#define IMPACTID_LEVEL_KERNELS(level_namespace)                                         \
  LevelKernels {                                                                        \
    level_namespace::simulate_rod_lanes, level_namespace::simulate_explicit_lanes,      \
        level_namespace::simulate_kr_alpha_lanes, level_namespace::simulate_chain_lanes, \
        level_namespace::multiply_add_lanes, level_namespace::simulate_model_lanes        \
  }

// The row of the level that runs; null on baseline.
const LevelKernels* level_kernels() {
  switch (kernel_level()) {
#if defined(IMPACTID_HAVE_KERNELS_V4)
    case KernelLevel::x86_64_v4: {
      static constexpr LevelKernels v4 = IMPACTID_LEVEL_KERNELS(kernels_x86_64_v4);
      return &v4;
    }
#endif
#if defined(IMPACTID_HAVE_KERNELS_V3)
    case KernelLevel::x86_64_v3: {
      static constexpr LevelKernels v3 = IMPACTID_LEVEL_KERNELS(kernels_x86_64_v3);
      return &v3;
    }
#endif
    default:  // baseline, or a level this build has no kernels of (never selected)
      return nullptr;
  }
}

// The baseline level: each run alone, its trace moved into the batch's.
template <class Scene>
void simulate_each(std::span<const Scene> scenes, std::span<const MethodParams> methods,
                   const RunOptions& options, SimulationWorkspace& scalar,
                   std::array<ContactTrace, kBatchLanes>& traces, std::span<RunSummary> summaries) {
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    if constexpr (std::is_pointer_v<Scene>) {
      summaries[k] = simulate(*scenes[k], methods[k], options, scalar);
    } else {
      summaries[k] = simulate(scenes[k], methods[k], options, scalar);
    }
    std::swap(traces[k], scalar.trace);
  }
}

}  // namespace

void simulate_batch(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                    const RunOptions& options, BatchWorkspace& ws,
                    std::span<RunSummary> summaries) {
  if (const LevelKernels* kernels = level_kernels()) {
    return kernels->rod(scenes, methods, options, {ws.storage_, ws.start_, ws.traces}, summaries);
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

void simulate_explicit_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchWorkspace& ws, std::span<RunSummary> summaries) {
  if (const LevelKernels* kernels = level_kernels()) {
    return kernels->explicit_methods(scenes, methods, options, {ws.storage_, ws.start_, ws.traces},
                                     summaries);
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

void simulate_kr_alpha_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             std::vector<LaneBlock>& blocks, std::array<State, kBatchLanes>& starts,
                             std::array<ContactTrace, kBatchLanes>& traces,
                             std::span<RunSummary> summaries) {
  if (const LevelKernels* kernels = level_kernels()) {
    return kernels->kr_alpha(scenes, methods, options, {blocks, starts, traces}, summaries);
  }
  SimulationWorkspace scalar;
  simulate_each(scenes, methods, options, scalar, traces, summaries);
}

void simulate_chain_batch(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          ChainBatchWorkspace& ws, std::span<RunSummary> summaries) {
  if (const LevelKernels* kernels = level_kernels()) {
    return kernels->chain(scenes, methods, options, ws.storage_, ws.start_, ws.integrators_,
                          ws.traces, summaries);
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

void multiply_add_lanes(const SparseMatrix& a, double s, std::span<const LaneBlock> x,
                        std::span<LaneBlock> y) {
  if (const LevelKernels* kernels = level_kernels()) return kernels->sparse_product(a, s, x, y);
  // Baseline x86-64: multiply_add's operations, lane by lane.
  for (int l = 0; l < kBatchLanes; ++l) {
    for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
      const double sx = s * x[static_cast<std::size_t>(j)].lane[l];
      if (sx == 0.0) continue;
      for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
        y[static_cast<std::size_t>(it.row())].lane[l] += it.value() * sx;
      }
    }
  }
}

void simulate_model_batch(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          ModelBatchWorkspace& ws, std::span<RunSummary> summaries) {
  if (const LevelKernels* kernels = level_kernels()) {
    return kernels->model(scenes, methods, options, ws.storage_, ws.states_, ws.steppers_,
                          ws.traces, ws.scalar_, ws.kernel_lanes_, summaries);
  }
  ws.kernel_lanes_ = 0;
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

}  // namespace impactid
