// How a converged reference runs its refined scenes. The references sit below the run layer
// (core/run/), which keeps their last results in its workspace, so they are handed the run as a
// callback rather than including it: core/run/references.hpp passes simulate().
//
// Thread safety: whatever the callback's; simulate() is reentrant.
#pragma once

#include <functional>

#include "core/common/run_record.hpp"
#include "core/methods/method.hpp"
#include "core/model/scene_assembly.hpp"

namespace impactid {

/// Runs `scene` with `method` and the default run options, from a fresh workspace; returns the
/// summary and leaves every contact's samples in `trace`.
using ReferenceRun = std::function<RunSummary(const AssembledScene& scene,
                                              const MethodParams& method, ContactTrace& trace)>;

}  // namespace impactid
