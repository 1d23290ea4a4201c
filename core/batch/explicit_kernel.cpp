// The rod's explicit kernels at one level (core/batch/batch_kernels.hpp; why and how:
// core/batch/batched_explicit.hpp): each sub-batch to its method's kernel, central difference's
// (core/batch/cdm_kernel.hpp), Noh–Bathe's (noh_bathe_kernel.hpp) or Kim's (kim_kernel.hpp). The
// kernels are headers of this one file: see core/batch/explicit_rows.hpp.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <initializer_list>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/common/parameter_error.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/contact/stable_step_warning.hpp"
#include "core/methods/central_difference.hpp"
#include "core/methods/kim_explicit.hpp"
#include "core/methods/noh_bathe.hpp"
#include "core/model/second_order_system.hpp"

// Last: the level's target for the rest of the file (core/batch/kernel_target.hpp), then the lane
// vocabulary and the kernels, compiled for the level (kept in this order: clang-format would sort
// them).
// clang-format off
#include "core/batch/kernel_target.hpp"
#include "core/batch/batch_lanes.hpp"
#include "core/batch/simd_lanes.hpp"
#include "core/batch/explicit_rows.hpp"
#include "core/batch/cdm_kernel.hpp"
#include "core/batch/explicit_stage.hpp"
#include "core/batch/noh_bathe_kernel.hpp"
#include "core/batch/kim_kernel.hpp"
// clang-format on

namespace impactid::IMPACTID_KERNEL_NAMESPACE {

void simulate_explicit_lanes(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchStorage workspace, std::span<RunSummary> summaries) {
  const ExplicitBatchKind kind = explicit_batch_kind(methods[0]);
  assert(kind != ExplicitBatchKind::none && "simulate_explicit_batch: not an explicit batch");
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    const auto sub_scenes = scenes.subspan(first, count);
    const auto sub_methods = methods.subspan(first, count);
    const auto sub_summaries = summaries.subspan(first, count);
    const LaneSpan<State> starts = sub_batch_part(workspace.starts, first);
    const LaneSpan<ContactTrace> traces = sub_batch_part(workspace.traces, first);
    switch (kind) {
      case ExplicitBatchKind::central_difference:
        simulate_cdm_batch(sub_scenes, sub_methods, options, workspace.blocks, starts, traces,
                           sub_summaries);
        return;
      case ExplicitBatchKind::noh_bathe:
        simulate_stage_batch<NohBatheLanes>(sub_scenes, sub_methods, options, workspace.blocks,
                                            starts, traces, sub_summaries);
        return;
      case ExplicitBatchKind::kim_explicit:
        simulate_stage_batch<KimLanes>(sub_scenes, sub_methods, options, workspace.blocks, starts,
                                       traces, sub_summaries);
        return;
      case ExplicitBatchKind::none:
        return;
    }
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
