// The public entry points of the batched kernels: each calls the level kernel_level() names
// (core/kernel_level.hpp). On baseline x86-64 no kernel is compiled: each run goes through
// simulate(), which gives the numbers the kernels give.
#include "core/batch_kernels.hpp"

#include <utility>

#include "core/batched_chain.hpp"
#include "core/batched_explicit.hpp"
#include "core/batched_kr_alpha.hpp"
#include "core/batched_simulation.hpp"
#include "core/kernel_level.hpp"

namespace impactid {
namespace {

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
  const BatchStorage storage{ws.storage_, ws.start_, ws.traces};
  switch (kernel_level()) {
#if defined(IMPACTID_HAVE_KERNELS_V4)
    case KernelLevel::x86_64_v4:
      return kernels_x86_64_v4::simulate_rod_lanes(scenes, methods, options, storage, summaries);
#endif
#if defined(IMPACTID_HAVE_KERNELS_V3)
    case KernelLevel::x86_64_v3:
      return kernels_x86_64_v3::simulate_rod_lanes(scenes, methods, options, storage, summaries);
#endif
    default:  // baseline, or a level this build has no kernels of (never selected)
      break;
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

void simulate_explicit_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchWorkspace& ws, std::span<RunSummary> summaries) {
  const BatchStorage storage{ws.storage_, ws.start_, ws.traces};
  switch (kernel_level()) {
#if defined(IMPACTID_HAVE_KERNELS_V4)
    case KernelLevel::x86_64_v4:
      return kernels_x86_64_v4::simulate_explicit_lanes(scenes, methods, options, storage,
                                                        summaries);
#endif
#if defined(IMPACTID_HAVE_KERNELS_V3)
    case KernelLevel::x86_64_v3:
      return kernels_x86_64_v3::simulate_explicit_lanes(scenes, methods, options, storage,
                                                        summaries);
#endif
    default:  // baseline, or a level this build has no kernels of (never selected)
      break;
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

void simulate_kr_alpha_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             std::vector<LaneBlock>& blocks, std::array<State, kBatchLanes>& starts,
                             std::array<ContactTrace, kBatchLanes>& traces,
                             std::span<RunSummary> summaries) {
  const BatchStorage storage{blocks, starts, traces};
  switch (kernel_level()) {
#if defined(IMPACTID_HAVE_KERNELS_V4)
    case KernelLevel::x86_64_v4:
      return kernels_x86_64_v4::simulate_kr_alpha_lanes(scenes, methods, options, storage,
                                                        summaries);
#endif
#if defined(IMPACTID_HAVE_KERNELS_V3)
    case KernelLevel::x86_64_v3:
      return kernels_x86_64_v3::simulate_kr_alpha_lanes(scenes, methods, options, storage,
                                                        summaries);
#endif
    default:  // baseline, or a level this build has no kernels of (never selected)
      break;
  }
  SimulationWorkspace scalar;
  simulate_each(scenes, methods, options, scalar, traces, summaries);
}

void simulate_chain_batch(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          ChainBatchWorkspace& ws, std::span<RunSummary> summaries) {
  switch (kernel_level()) {
#if defined(IMPACTID_HAVE_KERNELS_V4)
    case KernelLevel::x86_64_v4:
      return kernels_x86_64_v4::simulate_chain_lanes(
          scenes, methods, options, ws.storage_, ws.start_, ws.integrators_, ws.traces, summaries);
#endif
#if defined(IMPACTID_HAVE_KERNELS_V3)
    case KernelLevel::x86_64_v3:
      return kernels_x86_64_v3::simulate_chain_lanes(
          scenes, methods, options, ws.storage_, ws.start_, ws.integrators_, ws.traces, summaries);
#endif
    default:  // baseline, or a level this build has no kernels of (never selected)
      break;
  }
  simulate_each(scenes, methods, options, ws.scalar_, ws.traces, summaries);
}

}  // namespace impactid
