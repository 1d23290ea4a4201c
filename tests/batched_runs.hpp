// The check both batched-kernel tests make: runs as one batch through simulate_batch (the path a
// sweep takes) against each alone through simulate(), bit for bit.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "same_run.hpp"

namespace impactid::testing {

struct LaneRun {
  std::string name;
  RodScene scene;
  MethodParams method;
};

/// Runs `runs` as one batch and each alone through simulate(), and compares everything: the
/// summaries (the stable step and the warning too), the traces. Returns the scalar summaries,
/// so that callers can check that the batch covers what it claims.
inline std::vector<RunSummary> expect_batch_equals_scalar(const std::vector<LaneRun>& runs,
                                                          const RunOptions& options = {}) {
  std::vector<RodScene> scenes;
  std::vector<MethodParams> methods;
  for (const LaneRun& r : runs) {
    EXPECT_TRUE(batchable(r.scene, r.method, options)) << r.name;
    EXPECT_TRUE(same_batch(runs[0].scene, runs[0].method, options, r.scene, r.method, options))
        << r.name;
    scenes.push_back(r.scene);
    methods.push_back(r.method);
  }
  BatchWorkspace batch;
  std::vector<RunSummary> batched(runs.size());
  simulate_batch(scenes, methods, options, batch, batched);

  std::vector<RunSummary> scalars;
  SimulationWorkspace ws;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string& name = runs[k].name;
    const RunSummary s = simulate(runs[k].scene, runs[k].method, options, ws);
    expect_same_run(batched[k], batch.traces[k], s, ws.trace, name);
    EXPECT_TRUE(same(batched[k].stable_dt, s.stable_dt)) << name;
    EXPECT_EQ(batched[k].warning, s.warning) << name;
    scalars.push_back(s);
  }
  return scalars;
}

}  // namespace impactid::testing
