// The sweep driver: the same numbers on any thread count, an interrupted and resumed sweep
// equal to an uninterrupted one, and a plan point equal to the same simulation run alone.
#include "study/studies/sweep.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "study/formats/hdf5_file.hpp"
#include "study/io/results_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"

namespace impactid {
namespace {

// Small and fast, and with points that are not ok: Newmark δ = 0 chatters on the wall.
const char* kGridPlan = R"(
name = "sweep-test"
[scene]
elements = 40
[method]
name = "newmark"
[study]
kind = "grid"
[study.axes]
courant = { values = [0.5, 1.0] }
delta = { from = 0.0, to = 1.0, partitions = 10 }
[output]
checkpoint_seconds = 1000.0
)";

std::vector<long> all_points(const PointSet& points) {
  std::vector<long> indices(static_cast<std::size_t>(points.size()));
  for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<long>(i);
  return indices;
}

// Bit identity of everything but the wall time, NaNs included.
void expect_identical(const StudyResults& a, const StudyResults& b) {
  ASSERT_EQ(a.status, b.status);
  ASSERT_EQ(a.indicators.size(), b.indicators.size());
  for (std::size_t c = 0; c < a.indicators.size(); ++c) {
    if (a.indicators[c].name == "wall_time_s") continue;
    const auto& x = a.indicators[c].values;
    const auto& y = b.indicators[c].values;
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(double)), 0)
        << a.indicators[c].name;
  }
  for (std::size_t c = 0; c < a.parameters.size(); ++c) {
    const auto& x = a.parameters[c].values;
    const auto& y = b.parameters[c].values;
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(double)), 0)
        << a.parameters[c].name;
  }
}

StudyResults run_all(const Plan& plan, const PointSet& points, int threads) {
  StudyResults results = empty_results(plan, points);
  SweepOptions options;
  options.threads = threads;
  const auto indices = all_points(points);
  const SweepOutcome outcome = run_sweep(points, indices, results, options);
  EXPECT_EQ(outcome.computed, points.size());
  EXPECT_FALSE(outcome.interrupted);
  return results;
}

TEST(Sweep, SameNumbersOnOneAndSeveralThreads) {
  const Plan plan = parse_plan(kGridPlan, "sweep-test.toml");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 22);
  const StudyResults one = run_all(plan, points, 1);
  const StudyResults two = run_all(plan, points, 2);
  const StudyResults three = run_all(plan, points, 3);
  expect_identical(one, two);
  expect_identical(one, three);
  EXPECT_EQ(one.points_done(), 22);
  // The grid includes points that are not ok (δ = 0 chatters): recorded, not fatal.
  EXPECT_GT(std::count(one.status.begin(), one.status.end(), 1), 0);
}

TEST(Sweep, InterruptedThenResumedEqualsUninterrupted) {
  const Plan plan = parse_plan(kGridPlan, "sweep-test.toml");
  const PointSet points(plan);
  const auto indices = all_points(points);

  std::atomic<bool> stop{false};
  StudyResults partial = empty_results(plan, points);
  // One thread, so that the stop lands after the unit of work in which the 5th point finishes
  // (a window of up to kBatchLanes points, study/studies/sweep.hpp): progress is reported by the
  // calling thread only, and with more threads the others may finish everything first.
  SweepOptions options;
  options.threads = 1;
  options.progress_seconds = 0.0;
  options.progress = [&](const SweepProgress& p) {
    if (p.done >= 5) stop.store(true);
  };
  options.stop = &stop;
  const SweepOutcome first = run_sweep(points, indices, partial, options);
  EXPECT_TRUE(first.interrupted);
  EXPECT_GE(first.computed, 5);
  EXPECT_LE(first.computed, 5 + kBatchLanes - 1);
  EXPECT_LT(first.computed, points.size());
  EXPECT_EQ(partial.points_done(), first.computed);

  // Through the file, as `impactid run --resume` does.
  const std::string path = ::testing::TempDir() + "impactid_sweep_resume.h5";
  write_results(path, partial);
  StudyResults resumed = read_results(path);
  SweepOptions rest;
  rest.threads = 2;
  const SweepOutcome second = run_sweep(points, indices, resumed, rest);
  EXPECT_EQ(second.reused, first.computed);
  EXPECT_EQ(second.computed, points.size() - first.computed);

  expect_identical(resumed, run_all(plan, points, 1));
}

// Issue 38: a checkpoint that cannot be written (a full disk, a read-only file system) threw
// inside the OpenMP region and aborted the program. The error now leaves run_sweep as the
// exception it is, on any thread count, the windows after it skipped.
TEST(Sweep, AFailedCheckpointEndsTheSweepWithItsError) {
  const Plan plan = parse_plan(kGridPlan, "sweep-test.toml");
  const PointSet points(plan);
  const auto indices = all_points(points);
  for (const int threads : {1, 2}) {
    StudyResults results = empty_results(plan, points);
    SweepOptions options;
    options.threads = threads;
    options.checkpoint_seconds = 0.0;
    int calls = 0;
    options.checkpoint = [&](const StudyResults&) {
      ++calls;  // the calling thread only (study/studies/sweep.cpp)
      throw Hdf5Error("full.h5: cannot write full.h5.tmp: No space left on device");
    };
    bool thrown = false;
    try {
      run_sweep(points, indices, results, options);
    } catch (const Hdf5Error& e) {
      thrown = true;
      EXPECT_STREQ(e.what(), "full.h5: cannot write full.h5.tmp: No space left on device");
    }
    // The calling thread checkpoints; with two, on a loaded machine the other may take both
    // windows, and then there is no checkpoint to fail. Otherwise: one, and its error.
    EXPECT_EQ(calls, threads == 1 ? 1 : calls) << threads << " thread(s)";
    EXPECT_LE(calls, 1);
    EXPECT_EQ(thrown, calls == 1) << threads << " thread(s)";
    // 22 points are two windows: with one thread the second is skipped after the failure.
    if (threads == 1) EXPECT_EQ(results.points_done(), kBatchLanes);
  }
}

TEST(Sweep, PlanPointEqualsTheSameSimulationAlone) {
  const Plan plan = parse_plan(kGridPlan, "sweep-test.toml");
  const PointSet points(plan);
  const StudyResults results = run_all(plan, points, 2);
  // Point (courant = 1.0, delta = 0.3): row-major, last axis fastest.
  const long index = 1 * 11 + 3;
  SimulationSettings settings;
  settings.scene.elements = 40;
  settings.method.kind = MethodKind::newmark;
  ASSERT_FALSE(assign(settings, "courant", 1.0));
  ASSERT_FALSE(assign(settings, "delta", 0.3));
  SimulationWorkspace workspace;
  const Evaluation alone = evaluate(std::get<Simulation>(build(settings)), workspace);
  const ResultColumn* eps_p = results.find_column("eps_p");
  const ResultColumn* nop_p = results.find_column("nop_p");
  const ResultColumn* beta = results.find_column("beta");
  ASSERT_TRUE(eps_p && nop_p && beta);
  EXPECT_EQ(eps_p->values[index], alone.indicators.eps_p);
  EXPECT_EQ(nop_p->values[index], alone.indicators.nop_p);
  EXPECT_DOUBLE_EQ(beta->values[index], 0.25 * 1.3 * 1.3);
  EXPECT_EQ(results.status[index], 0);
}

// A choice axis: each point of `contact` x `penalty_factor` equals the same simulation run alone,
// bit for bit; the results table carries the words and writes them as CF flags.
TEST(Sweep, ChoiceAxisPointsEqualTheirSimulationsAlone) {
  const Plan plan = parse_plan(R"(
[scene]
elements = 40
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
contact = { values = ["lagrange", "penalty", "augmented-lagrangian"] }
penalty_factor = { values = [1.0, 100.0] }
)",
                               "choice-axis.toml");
  const PointSet points(plan);
  const StudyResults results = run_all(plan, points, 2);
  ASSERT_EQ(results.dimensions[0].labels,
            (std::vector<std::string>{"lagrange", "penalty", "augmented-lagrangian"}));
  const ResultColumn* eps_p = results.find_column("eps_p");
  const ResultColumn* penetration = results.find_column("max_penetration");
  ASSERT_TRUE(eps_p && penetration);
  const char* laws[] = {"lagrange", "penalty", "augmented-lagrangian"};
  for (long law = 0; law < 3; ++law) {
    for (long f = 0; f < 2; ++f) {
      SimulationSettings settings;
      settings.scene.elements = 40;
      settings.method.kind = MethodKind::hht;
      ASSERT_FALSE(assign(settings, "contact", std::string(laws[law])));
      ASSERT_FALSE(assign(settings, "penalty_factor", f == 0 ? 1.0 : 100.0));
      SimulationWorkspace workspace;
      const Evaluation alone = evaluate(std::get<Simulation>(build(settings)), workspace);
      const long index = law * 2 + f;
      EXPECT_EQ(results.status[index], 0) << laws[law];
      EXPECT_EQ(eps_p->values[index], alone.indicators.eps_p) << laws[law] << " " << f;
    }
  }
  // Penalty springs let the rod into the wall, less at the stiffer k; Lagrange does not.
  EXPECT_GT(penetration->values[2], penetration->values[3]);
  EXPECT_GT(penetration->values[3], 0.0);
  EXPECT_NE(eps_p->values[2], eps_p->values[0]);
}

}  // namespace
}  // namespace impactid
