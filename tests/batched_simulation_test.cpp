// simulate_batch(): every lane gives simulate()'s numbers bit for bit (issue 3: a plan point and
// `impactid simulate` agree exactly, and sweeps run points in batches), whatever the other lanes
// do; and which runs may share a batch.
#include "core/batch/batched_simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "batched_runs.hpp"

namespace impactid {
namespace {

using testing::expect_batch_equals_scalar;
using testing::LaneRun;

// A full batch of every implicit method, one lane unstable, lanes with other gaps (so other
// free flights, impact times and step counts) and another velocity.
TEST(BatchedSimulation, EveryLaneEqualsTheScalarRunBitForBit) {
  RodScene far_gap_scene;
  far_gap_scene.gap = 0.2;  // 428 free-flight steps instead of 19, 1650 steps instead of 1222
  RodScene slow;
  slow.velocity = 300.0;
  slow.gap = 0.05;
  RodScene touching;
  touching.gap = 0.0;  // no free flight at all
  RodScene short_run;
  short_run.t_end = 2e-4;  // ends during the contact
  RodScene away;
  away.velocity = -500.0;  // never reaches the wall
  RodScene fast;
  fast.velocity = 5000.0;
  const std::vector<LaneRun> runs = {
      {"hht", RodScene{}, HhtParams{.alpha = -0.3}},
      {"hht unstable", RodScene{}, HhtParams{.alpha = -0.5, .delta = 0.0}},
      {"generalized-alpha (alpha_m != 0)", RodScene{}, GeneralizedAlphaParams{.rho_inf = 0.6}},
      {"newmark, gap 0.2", far_gap_scene, NewmarkParams{.delta = 0.3}},
      {"backward-euler, slow", slow, BackwardEulerParams{}},
      {"hht weighted", RodScene{}, HhtParams{.alpha = -0.1, .contact = ContactWeighting::weighted}},
      {"newmark beta-gamma, gap 0", touching,
       NewmarkParams{.coefficients = BetaGamma{0.3025, 0.6}}},
      {"generalized-alpha weighted", RodScene{},
       GeneralizedAlphaParams{.rho_inf = 0.5, .contact = ContactWeighting::weighted}},
      {"trapezoidal (chatters, energy grows)", RodScene{}, NewmarkParams{.delta = 0.0}},
      {"hht eq. 19", RodScene{}, HhtParams{.alpha = -0.5, .delta = 0.75}},
      {"newmark, short run", short_run, NewmarkParams{.delta = 1.0}},
      {"hht, moving away", away, HhtParams{.alpha = -0.2}},
      {"backward-euler", RodScene{}, BackwardEulerParams{}},
      {"generalized-alpha rho_inf 0", RodScene{}, GeneralizedAlphaParams{.rho_inf = 0.0}},
      {"hht alpha 0", touching, HhtParams{.alpha = 0.0, .delta = 0.2}},
      {"newmark, fast", fast, NewmarkParams{.delta = 0.5}},
  };
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  // The batch covers what it claims: one lane stops early while the others run on, and the
  // lanes start and end at different samples.
  EXPECT_EQ(scalar[1].status, RunStatus::unstable);
  EXPECT_LT(scalar[1].steps, scalar[0].steps);
  EXPECT_EQ(scalar[0].status, RunStatus::ok);
  EXPECT_NE(scalar[3].skipped_steps, scalar[0].skipped_steps);
  EXPECT_NE(scalar[3].planned_steps, scalar[0].planned_steps);
  EXPECT_EQ(scalar[6].skipped_steps, 0);
}

// Fewer runs than lanes, on a damped rod with a consistent mass (the damping terms and no
// free-flight skip: mass-proportional damping slows the rod in flight).
TEST(BatchedSimulation, PartialBatchOnADampedRodEqualsScalarRuns) {
  RodScene damped;
  damped.mass = MassMatrix::consistent;
  damped.rayleigh_mass = 200.0;
  damped.rayleigh_stiffness = 2e-8;
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  expect_batch_equals_scalar({
      {"hht", damped, HhtParams{.alpha = -0.2}},
      {"generalized-alpha", damped, GeneralizedAlphaParams{.rho_inf = 0.9}},
      {"newmark", damped, NewmarkParams{.delta = 0.5}},
  });
  expect_batch_equals_scalar({{"hht", stiffness_damped, HhtParams{}}});
}

// Options the scalar path reports as failed fail every lane the same way; a coarse energy check
// interval and stepped free flight are honoured.
TEST(BatchedSimulation, RunOptionsAreHonouredLaneByLane) {
  const std::vector<LaneRun> runs = {
      {"hht", RodScene{}, HhtParams{}},
      {"hht unstable", RodScene{}, HhtParams{.alpha = -0.5, .delta = 0.0}},
  };
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 50,
                                              .skip_free_flight = false});
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);

  // An overflow between energy checks: the lane stops at the sample where λ or the velocity
  // first is not finite (the batch checks every sample, though it visits the lanes one by one
  // only at events), while a stable lane runs on. Explicit-like Newmark (β = 0.01, γ = 1/2)
  // at Courant 3 overflows after about a hundred steps.
  RodScene coarse;
  coarse.courant = 3.0;
  const std::vector<RunSummary> overflow = expect_batch_equals_scalar(
      {{"newmark, overflows", coarse, NewmarkParams{.coefficients = BetaGamma{0.01, 0.5}}},
       {"hht", coarse, HhtParams{}}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
  EXPECT_EQ(overflow[0].status, RunStatus::unstable);
  EXPECT_NE(overflow[0].message.find("non-finite"), std::string::npos) << overflow[0].message;
  EXPECT_LT(overflow[0].steps, overflow[0].planned_steps);
  EXPECT_EQ(overflow[1].status, RunStatus::ok);
}

// The batch stops stepping once no lane steps or will start (core/batch/rod_kernel.cpp), but
// not before a lane that starts late: here the first lane is unstable before the second lane's
// free flight ends, and the second still runs, as alone.
TEST(BatchedSimulation, ALaneStartingAfterTheOthersEndedStillRuns) {
  RodScene late;
  late.gap = 0.2;  // free flight to 0.2 ms, about half the run
  late.t_end = 1e-3;
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar({
      {"hht unstable", RodScene{}, HhtParams{.alpha = -0.5, .delta = 0.0}},
      {"hht unstable, late", late, HhtParams{.alpha = -0.5, .delta = 0.0}},
      {"hht, late", late, HhtParams{}},
  });
  EXPECT_EQ(scalar[0].status, RunStatus::unstable);
  EXPECT_EQ(scalar[1].status, RunStatus::unstable);
  EXPECT_EQ(scalar[2].status, RunStatus::ok);
  EXPECT_LT(scalar[0].steps, scalar[1].skipped_steps)
      << "the first lane ends before the others start";
}

// The composite schemes (core/methods/bathe_composite.hpp: two implicit sub-steps a step, the first
// over γ·Δt) in a full batch: Bathe, TR-BDF2 and ρ∞-Bathe over ρ∞ and γ (γ per lane), lanes that go
// unstable (the trapezoidal first sub-step chatters: ρ∞ = 1, 0.3), other gaps, velocities and
// end times.
TEST(BatchedSimulation, CompositeLanesEqualTheScalarRunBitForBit) {
  RodScene far_gap_scene;
  far_gap_scene.gap = 0.2;
  RodScene slow;
  slow.velocity = 300.0;
  slow.gap = 0.05;
  RodScene touching;
  touching.gap = 0.0;
  RodScene short_run;
  short_run.t_end = 2e-4;
  RodScene away;
  away.velocity = -500.0;
  RodScene fast;
  fast.velocity = 5000.0;
  const std::vector<LaneRun> runs = {
      {"rho-bathe", RodScene{}, RhoBatheParams{}},
      {"bathe", RodScene{}, BatheParams{}},
      {"rho-bathe rho_inf 1 (unstable)", RodScene{}, RhoBatheParams{.rho_inf = 1.0}},
      {"tr-bdf2, gap 0.2", far_gap_scene, TrBdf2Params{}},
      {"rho-bathe 0.3 (unstable)", RodScene{}, RhoBatheParams{.rho_inf = 0.3}},
      {"rho-bathe gamma 0.1, slow", slow, RhoBatheParams{.rho_inf = 0.0, .gamma = 0.1}},
      {"rho-bathe gamma 0.9, gap 0", touching, RhoBatheParams{.rho_inf = 0.2, .gamma = 0.9}},
      {"bathe, short run", short_run, BatheParams{}},
      {"rho-bathe, moving away", away, RhoBatheParams{.rho_inf = 0.5}},
      {"rho-bathe, fast", fast, RhoBatheParams{.rho_inf = 0.1, .gamma = 0.35}},
      {"rho-bathe 0.6", RodScene{}, RhoBatheParams{.rho_inf = 0.6}},
      {"rho-bathe 0.05 gamma 0.6", RodScene{}, RhoBatheParams{.rho_inf = 0.05, .gamma = 0.6}},
      {"rho-bathe 1 gamma 0.5", touching, RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}},
      {"tr-bdf2", RodScene{}, TrBdf2Params{}},
      {"rho-bathe 0.9 gamma 0.2", far_gap_scene, RhoBatheParams{.rho_inf = 0.9, .gamma = 0.2}},
      {"bathe, slow", slow, BatheParams{}},
  };
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  EXPECT_EQ(scalar[0].status, RunStatus::ok) << scalar[0].message;
  EXPECT_EQ(scalar[2].status, RunStatus::unstable);
  EXPECT_LT(scalar[2].steps, scalar[0].steps);
  EXPECT_NE(scalar[3].skipped_steps, scalar[0].skipped_steps);
  EXPECT_NE(scalar[3].planned_steps, scalar[0].planned_steps);
  EXPECT_EQ(scalar[6].skipped_steps, 0);
  EXPECT_LT(scalar[7].planned_steps, scalar[0].planned_steps);
}

// The composite schemes on a damped rod with a consistent mass and on one with a lumped mass and
// stiffness damping; run options honoured; a lane that overflows between energy checks.
TEST(BatchedSimulation, CompositeLanesOnDampedRodsAndWithRunOptions) {
  RodScene damped;
  damped.mass = MassMatrix::consistent;
  damped.rayleigh_mass = 200.0;
  damped.rayleigh_stiffness = 2e-8;
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  for (const RodScene& scene : {damped, stiffness_damped, consistent}) {
    expect_batch_equals_scalar({
        {"rho-bathe", scene, RhoBatheParams{.rho_inf = 0.2}},
        {"bathe", scene, BatheParams{}},
        {"rho-bathe gamma 0.7", scene, RhoBatheParams{.rho_inf = 0.8, .gamma = 0.7}},
    });
  }
  const std::vector<LaneRun> runs = {
      {"rho-bathe", RodScene{}, RhoBatheParams{}},
      {"rho-bathe unstable", RodScene{}, RhoBatheParams{.rho_inf = 1.0}},
  };
  expect_batch_equals_scalar(runs,
                             RunOptions{.energy_check_interval = 50, .skip_free_flight = false});
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);
  // No energy bound to speak of: a lane whose values overflow stops at the first non-finite
  // sample, between energy checks, while the others run on.
  RodScene coarse;
  coarse.courant = 3.0;
  const std::vector<RunSummary> overflow = expect_batch_equals_scalar(
      {{"rho-bathe 1", coarse, RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}},
       {"rho-bathe 0.3 gamma 0.1", coarse, RhoBatheParams{.rho_inf = 0.3, .gamma = 0.1}},
       {"rho-bathe", coarse, RhoBatheParams{}}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
  EXPECT_EQ(overflow[2].status, RunStatus::ok) << overflow[2].message;
}

// Wilson-θ (core/methods/wilson_theta.hpp: one extended step over θ·Δt, the interpolation back to
// Δt, the wall's constraint at the samples through a shifted gap) in a full batch: θ per lane,
// lanes that go unstable at different samples (on the paper's scene every θ does, REPRODUCTION.md)
// among lanes that end ok (runs that end in the contact before the energy has grown, a rod moving
// away; a lifted energy bound is a run option, the same for a batch: the next test), other gaps,
// velocities and end times.
TEST(BatchedSimulation, WilsonThetaLanesEqualTheScalarRunBitForBit) {
  RodScene far_gap_scene;
  far_gap_scene.gap = 0.2;
  RodScene slow;
  slow.velocity = 300.0;
  slow.gap = 0.05;
  RodScene touching;
  touching.gap = 0.0;
  RodScene short_run;
  short_run.t_end = 2e-5;  // ends during the contact, before the energy has grown
  RodScene shorter_run;
  shorter_run.t_end = 1.5e-5;
  RodScene away;
  away.velocity = -500.0;  // never reaches the wall
  RodScene fast;
  fast.velocity = 5000.0;
  const std::vector<LaneRun> runs = {
      {"wilson-theta (unstable)", RodScene{}, WilsonThetaParams{}},
      {"wilson-theta 2, short run", short_run, WilsonThetaParams{.theta = 2.0}},
      {"wilson-theta, shorter run", shorter_run, WilsonThetaParams{}},
      {"wilson-theta 1.5, gap 0.2", far_gap_scene, WilsonThetaParams{.theta = 1.5}},
      {"wilson-theta 3, moving away", away, WilsonThetaParams{.theta = 3.0}},
      {"wilson-theta 1.37, slow", slow, WilsonThetaParams{.theta = 1.37}},
      {"wilson-theta 2.5, gap 0", touching, WilsonThetaParams{.theta = 2.5}},
      {"wilson-theta 1.8, fast", fast, WilsonThetaParams{.theta = 1.8}},
      {"wilson-theta 1.45", RodScene{}, WilsonThetaParams{.theta = 1.45}},
      {"wilson-theta 1.7, short run", short_run, WilsonThetaParams{.theta = 1.7}},
      {"wilson-theta 2.2", RodScene{}, WilsonThetaParams{.theta = 2.2}},
      {"wilson-theta 1.6, shorter run", shorter_run, WilsonThetaParams{.theta = 1.6}},
      {"wilson-theta 2.8, gap 0.2", far_gap_scene, WilsonThetaParams{.theta = 2.8}},
      {"wilson-theta, moving away", away, WilsonThetaParams{}},
      {"wilson-theta 1.9, slow", slow, WilsonThetaParams{.theta = 1.9}},
      {"wilson-theta 4, short run", short_run, WilsonThetaParams{.theta = 4.0}},
  };
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  EXPECT_EQ(scalar[0].status, RunStatus::unstable);
  EXPECT_LT(scalar[0].steps, scalar[0].planned_steps);
  for (const std::size_t ok : {1, 2, 4, 9, 11, 13, 15}) {
    EXPECT_EQ(scalar[ok].status, RunStatus::ok) << runs[ok].name << ": " << scalar[ok].message;
  }
  for (const std::size_t unstable : {3, 5, 6, 7, 8, 10, 12, 14}) {
    EXPECT_EQ(scalar[unstable].status, RunStatus::unstable) << runs[unstable].name;
  }
  // The short runs end in the contact (which Wilson-θ's chatter opens and closes): the wall
  // pushes in them.
  SimulationWorkspace ws;
  EXPECT_EQ(simulate(short_run, WilsonThetaParams{.theta = 2.0}, RunOptions{}, ws).status,
            RunStatus::ok);
  EXPECT_GT(*std::max_element(ws.trace.pressure.begin(), ws.trace.pressure.end()), 0.0);
  EXPECT_NE(scalar[3].skipped_steps, scalar[0].skipped_steps);
  EXPECT_EQ(scalar[6].skipped_steps, 0);
  EXPECT_LT(scalar[1].planned_steps, scalar[0].planned_steps);
}

// Wilson-θ on damped rods, a consistent mass, another Courant number (one per batch), a partial
// batch; run options (the energy bound lifted: every lane runs to its end; energy checked every
// step) honoured lane by lane; a lane whose values overflow between energy checks.
TEST(BatchedSimulation, WilsonThetaLanesOnOtherRodsAndWithRunOptions) {
  RodScene damped;
  damped.mass = MassMatrix::consistent;
  damped.rayleigh_mass = 200.0;
  damped.rayleigh_stiffness = 2e-8;
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  RodScene coarse;
  coarse.courant = 2.0;
  RodScene fine;
  fine.courant = 0.25;
  fine.t_end = 3e-4;
  for (const RodScene& scene : {damped, stiffness_damped, consistent, coarse, fine}) {
    RodScene short_run = scene;
    short_run.t_end = 1e-4;
    RodScene slow = scene;
    slow.velocity = 200.0;
    expect_batch_equals_scalar({
        {"wilson-theta", scene, WilsonThetaParams{}},
        {"wilson-theta 2", scene, WilsonThetaParams{.theta = 2.0}},
        {"wilson-theta 1.5, short run", short_run, WilsonThetaParams{.theta = 1.5}},
        {"wilson-theta 2.6, slow", slow, WilsonThetaParams{.theta = 2.6}},
    });
  }
  const std::vector<LaneRun> runs = {
      {"wilson-theta", RodScene{}, WilsonThetaParams{}},
      {"wilson-theta 2", RodScene{}, WilsonThetaParams{.theta = 2.0}},
      {"wilson-theta 3", RodScene{}, WilsonThetaParams{.theta = 3.0}},
  };
  const std::vector<RunSummary> lifted =
      expect_batch_equals_scalar(runs, RunOptions{.energy_growth_limit = 1000.0});
  for (const RunSummary& s : lifted) EXPECT_EQ(s.status, RunStatus::ok) << s.message;
  expect_batch_equals_scalar(runs,
                             RunOptions{.energy_check_interval = 50, .skip_free_flight = false});
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);
  RodScene very_coarse;
  very_coarse.courant = 3.0;
  expect_batch_equals_scalar(
      {{"wilson-theta", very_coarse, WilsonThetaParams{}},
       {"wilson-theta 1.5", very_coarse, WilsonThetaParams{.theta = 1.5}},
       {"wilson-theta 2", very_coarse, WilsonThetaParams{.theta = 2.0}}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
}

// Houbolt (core/methods/houbolt.hpp: a three-step method started by a cubic on the initial velocity
// and acceleration, two start-up steps with their own effective matrices, the contact at the
// samples) in a full batch: lanes that start stepping at different samples (free flights of
// different lengths, each lane's start-up then at its own samples), other gaps, velocities and
// end times, a rod moving away and one touching the wall at t = 0.
TEST(BatchedSimulation, HouboltLanesEqualTheScalarRunBitForBit) {
  std::vector<LaneRun> runs;
  for (const double gap : {0.0, 0.01, 0.05, 0.2}) {
    for (const double velocity : {-500.0, 300.0, 1000.0, 5000.0}) {
      RodScene scene;
      scene.gap = gap;
      scene.velocity = velocity;
      scene.t_end = runs.size() % 3 == 0 ? 2e-5 : runs.size() % 3 == 1 ? 1e-4 : scene.t_end;
      runs.push_back({"houbolt, gap " + std::to_string(gap) + ", v " + std::to_string(velocity),
                      scene, HouboltParams{}});
    }
  }
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  // Free flights of different lengths: the lanes start at different samples, and the lanes
  // touching the wall at t = 0 at the first.
  EXPECT_EQ(scalar[1].skipped_steps, 0);
  EXPECT_NE(scalar[9].skipped_steps, scalar[5].skipped_steps);
  EXPECT_GT(scalar[13].skipped_steps, scalar[9].skipped_steps);
  SimulationWorkspace ws;
  EXPECT_EQ(simulate(runs[6].scene, HouboltParams{}, RunOptions{}, ws).status, RunStatus::ok);
  EXPECT_GT(*std::max_element(ws.trace.pressure.begin(), ws.trace.pressure.end()), 0.0);
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  expect_batch_equals_scalar(runs,
                             RunOptions{.energy_check_interval = 50, .skip_free_flight = false});
}

// Houbolt on damped rods, a consistent mass, other Courant numbers (one per batch), partial
// batches; an energy bound that some lanes exceed (unstable) while the others run on; a bad
// check interval (failed).
TEST(BatchedSimulation, HouboltLanesOnOtherRodsAndWithRunOptions) {
  RodScene damped;
  damped.mass = MassMatrix::consistent;
  damped.rayleigh_mass = 200.0;
  damped.rayleigh_stiffness = 2e-8;
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  RodScene coarse;
  coarse.courant = 2.0;
  RodScene very_coarse;
  very_coarse.courant = 10.0;
  RodScene fine;
  fine.courant = 0.25;
  fine.t_end = 3e-4;
  for (const RodScene& scene : {damped, stiffness_damped, consistent, coarse, very_coarse, fine}) {
    RodScene short_run = scene;
    short_run.t_end = 1e-4;
    RodScene slow = scene;
    slow.velocity = 200.0;
    slow.gap = 0.0;
    RodScene away = scene;
    away.velocity = -100.0;
    expect_batch_equals_scalar({
        {"houbolt", scene, HouboltParams{}},
        {"houbolt, short run", short_run, HouboltParams{}},
        {"houbolt, slow, gap 0", slow, HouboltParams{}},
        {"houbolt, moving away", away, HouboltParams{}},
    });
  }
  // An energy bound barely above 1 (checked at every sample): a rod touching the wall at t = 0
  // gains energy in its first step (the start-up's linear-acceleration step), and a slow rod
  // far from the wall exceeds the bound late in its run (after 10'000 samples), while the
  // other lanes run to their ends.
  std::vector<LaneRun> runs;
  for (const double gap : {0.0, 0.003, 0.01, 0.05}) {
    for (const double velocity : {10.0, 1000.0, 5000.0}) {
      RodScene scene;
      scene.gap = gap;
      scene.velocity = velocity;
      runs.push_back({"houbolt, gap " + std::to_string(gap) + ", v " + std::to_string(velocity),
                      scene, HouboltParams{}});
    }
  }
  const std::vector<RunSummary> tight = expect_batch_equals_scalar(
      runs, RunOptions{.energy_growth_limit = 1.0 + 1e-12, .energy_check_interval = 1});
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const bool unstable = k < 3 || k == 9;
    EXPECT_EQ(tight[k].status, unstable ? RunStatus::unstable : RunStatus::ok) << runs[k].name;
  }
  EXPECT_EQ(tight[0].steps, 1);
  EXPECT_GT(tight[9].steps, 10'000);  // late in its run (and after other lanes' ends)
  EXPECT_LT(tight[9].steps, tight[9].planned_steps);
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);
}

TEST(BatchedSimulation, WhatMayShareABatch) {
  const RunOptions options;
  EXPECT_TRUE(batchable(RodScene{}, HhtParams{}, options));
  // Central difference batches too, in its own kernel (tests/batched_explicit_test.cpp).
  EXPECT_TRUE(batchable(RodScene{}, CentralDifferenceParams{}, options));
  EXPECT_FALSE(batchable(RodScene{}, HhtParams{}, RunOptions{.record_history = true}));
  // The kernel solves Lagrange multipliers only: another contact law runs in simulate().
  for (ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    RunOptions penalty;
    penalty.contact.law = law;
    EXPECT_FALSE(batchable(RodScene{}, HhtParams{}, penalty)) << to_string(law);
  }
  RodScene two_walls;
  two_walls.far_gap = 0.1;
  EXPECT_FALSE(batchable(two_walls, HhtParams{}, options));

  RodScene other_gap;
  other_gap.gap = 0.3;
  other_gap.velocity = 10.0;
  other_gap.t_end = 1e-3;
  const MethodParams hht = HhtParams{};
  EXPECT_TRUE(same_batch(RodScene{}, hht, options, other_gap, NewmarkParams{}, options));
  RodScene other_rod;
  other_rod.youngs_modulus = 100.0;  // other matrices and time step
  EXPECT_FALSE(same_batch(RodScene{}, hht, options, other_rod, hht, options));
  RodScene other_dt;
  other_dt.courant = 0.4;
  EXPECT_FALSE(same_batch(RodScene{}, hht, options, other_dt, hht, options));
  EXPECT_FALSE(same_batch(RodScene{}, hht, options, RodScene{}, hht,
                          RunOptions{.energy_growth_limit = 2.0}));

  // The composite schemes batch, among themselves, each lane its own ρ∞ and sub-step ratio γ;
  // not with the single-step methods (a batch steps one kind of step).
  for (const MethodParams& composite : {MethodParams{BatheParams{}}, MethodParams{RhoBatheParams{}},
                                        MethodParams{TrBdf2Params{}}}) {
    EXPECT_TRUE(batchable(RodScene{}, composite, options));
    EXPECT_FALSE(batchable(RodScene{}, composite, RunOptions{.record_history = true}));
    EXPECT_FALSE(batchable(two_walls, composite, options));
    EXPECT_FALSE(same_batch(RodScene{}, hht, options, RodScene{}, composite, options));
    EXPECT_FALSE(same_batch(RodScene{}, composite, options, RodScene{}, hht, options));
    EXPECT_TRUE(same_batch(RodScene{}, composite, options, other_gap,
                           RhoBatheParams{.rho_inf = 0.4, .gamma = 0.3}, options));
  }
  for (const ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    RunOptions penalty = options;
    penalty.contact.law = law;
    EXPECT_FALSE(batchable(RodScene{}, RhoBatheParams{}, penalty)) << to_string(law);
  }
  // Wilson-θ batches with Wilson-θ only, each lane its own θ; its penalty laws are not offered
  // (simulate() says so).
  const MethodParams wilson = WilsonThetaParams{};
  EXPECT_TRUE(batchable(RodScene{}, wilson, options));
  EXPECT_FALSE(batchable(RodScene{}, wilson, RunOptions{.record_history = true}));
  EXPECT_FALSE(batchable(two_walls, wilson, options));
  EXPECT_TRUE(
      same_batch(RodScene{}, wilson, options, other_gap, WilsonThetaParams{.theta = 2.0}, options));
  EXPECT_FALSE(same_batch(RodScene{}, wilson, options, other_dt, wilson, options));
  for (const MethodParams& other : {hht, MethodParams{BatheParams{}}}) {
    EXPECT_FALSE(same_batch(RodScene{}, wilson, options, RodScene{}, other, options));
    EXPECT_FALSE(same_batch(RodScene{}, other, options, RodScene{}, wilson, options));
  }
  RunOptions penalty = options;
  penalty.contact.law = ContactLaw::penalty;
  EXPECT_FALSE(batchable(RodScene{}, wilson, penalty));
  // Houbolt batches with Houbolt only (its own kind of step).
  const MethodParams houbolt = HouboltParams{};
  EXPECT_TRUE(batchable(RodScene{}, houbolt, options));
  EXPECT_FALSE(batchable(RodScene{}, houbolt, RunOptions{.record_history = true}));
  EXPECT_FALSE(batchable(two_walls, houbolt, options));
  EXPECT_FALSE(batchable(RodScene{}, houbolt, penalty));
  EXPECT_TRUE(same_batch(RodScene{}, houbolt, options, other_gap, houbolt, options));
  EXPECT_FALSE(same_batch(RodScene{}, houbolt, options, other_dt, houbolt, options));
  for (const MethodParams& other : {hht, MethodParams{BatheParams{}}, wilson}) {
    EXPECT_FALSE(same_batch(RodScene{}, houbolt, options, RodScene{}, other, options));
    EXPECT_FALSE(same_batch(RodScene{}, other, options, RodScene{}, houbolt, options));
  }
}

}  // namespace
}  // namespace impactid
