// KR-α on the rod's batched kernel (core/batch/batched_kr_alpha.hpp): every lane gives simulate()'s
// numbers bit for bit, whatever the other lanes do (lanes with their own ρ∞, gap, velocity and end
// time, lanes in contact at the start, lanes that stop on the energy bound among lanes that run on,
// batches smaller than kBatchLanes); and which runs may share a batch.
#include "core/batch/batched_kr_alpha.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "batched_runs.hpp"
#include "core/batch/batched_simulation.hpp"

namespace impactid {
namespace {

using testing::expect_batch_equals_scalar;
using testing::LaneRun;

// Scenes of one rod and time step that differ in everything a lane may have of its own: ρ∞ (so
// D, E and their factorisations), gap (so the free flight, the impact and the number of steps),
// velocity, end time.
std::vector<LaneRun> kr_alpha_lanes(const RodScene& base, const std::string& what) {
  const auto scene = [&](double gap, double velocity, std::optional<double> t_end) {
    RodScene s = base;
    s.gap = gap;
    s.velocity = velocity;
    s.t_end = t_end;
    return s;
  };
  const auto run = [&](const std::string& name, const RodScene& s, double rho_inf) {
    return LaneRun{what + " " + name + ", rho_inf " + std::to_string(rho_inf), s,
                   KrAlphaParams{.rho_inf = rho_inf}};
  };
  return {
      run("default", base, 0.8),
      run("non-dissipative", base, 1.0),
      run("gap 0.2", scene(0.2, 1000.0, {}), 0.5),
      run("gap 0 (no free flight)", scene(0.0, 1000.0, {}), 0.0),
      run("slow", scene(0.05, 300.0, {}), 0.9),
      run("fast", scene(0.01, 5000.0, {}), 0.3),
      run("short run", scene(0.01, 1000.0, 2e-4), 0.8),
      run("moving away", scene(0.01, -500.0, {}), 0.6),
      run("gap 0.1", scene(0.1, 700.0, 1.5e-3), 0.95),
      run("gap 0.03", scene(0.03, 2000.0, {}), 0.2),
      run("end 5e-4", scene(0.0, 1500.0, 5e-4), 0.8),
      run("slowest", scene(0.02, 100.0, {}), 0.7),
      run("gap 0.15", scene(0.15, 1000.0, 1e-3), 0.4),
      run("gap 0.001", scene(0.001, 1000.0, {}), 0.85),
      run("fast, dissipative", scene(0.05, 3000.0, {}), 0.1),
      run("at rest", scene(0.01, 0.0, 3e-4), 0.8),
  };
}

// Full batches below, at and far above the explicit methods' Courant limit (KR-α is
// unconditionally stable), on a lumped and a consistent mass.
TEST(BatchedKrAlpha, LanesEqualTheScalarRunBitForBit) {
  for (const double courant : {0.5, 1.0, 4.0, 0.3}) {
    for (const MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
      RodScene base;
      base.courant = courant;
      base.mass = mass;
      const std::string what = "courant " + std::to_string(courant) +
                               (mass == MassMatrix::lumped ? " lumped" : " consistent");
      const std::vector<LaneRun> runs = kr_alpha_lanes(base, what);
      ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
      const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
      // The batch covers what it claims: lanes start and end at different samples, every lane
      // runs to its end, the contact is reached, and a lane touches the wall at its start.
      EXPECT_EQ(scalar[0].status, RunStatus::ok) << what << ": " << scalar[0].message;
      EXPECT_EQ(scalar[0].steps, scalar[0].planned_steps) << what;
      EXPECT_NE(scalar[2].skipped_steps, scalar[0].skipped_steps) << what;
      EXPECT_NE(scalar[2].planned_steps, scalar[0].planned_steps) << what;
      EXPECT_EQ(scalar[3].skipped_steps, 0) << what;
      EXPECT_LT(scalar[6].planned_steps, scalar[0].planned_steps) << what;
      EXPECT_TRUE(std::isnan(scalar[0].stable_dt))
          << what;  // unconditionally stable: none reported
    }
  }
  // The pressures of a default lane: the contact is reached, so the correction paths ran.
  RodScene base;
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(kr_alpha_lanes(base, "again"));
  SimulationWorkspace ws;
  simulate(base, KrAlphaParams{}, RunOptions{}, ws);
  double largest = 0.0;
  for (const double p : ws.trace.pressure) largest = std::max(largest, p);
  EXPECT_GT(largest, 0.0);
}

// Lanes in contact at the start (gap 0: the start's multiplier corrects a₀) before lanes of the
// same velocity, which start from the uncorrected a₀.
TEST(BatchedKrAlpha, LanesInContactAtTheStart) {
  RodScene touching;
  touching.gap = 0.0;
  touching.velocity = 300.0;
  touching.courant = 0.25;
  RodScene free = touching;
  free.gap = 0.01;
  const std::vector<RunSummary> scalar =
      expect_batch_equals_scalar({{"gap 0, rho_inf 0.8", touching, KrAlphaParams{}},
                                  {"gap 0, rho_inf 0.5", touching, KrAlphaParams{.rho_inf = 0.5}},
                                  {"gap 0.01, rho_inf 1", free, KrAlphaParams{.rho_inf = 1.0}}});
  SimulationWorkspace ws;
  simulate(touching, KrAlphaParams{}, RunOptions{.energy_check_interval = 1}, ws);
  EXPECT_GT(ws.trace.pressure[0], 0.0) << "the first sample is in contact";
  EXPECT_EQ(scalar[2].status, RunStatus::ok);
}

// A batch of one; a lane that starts after the others; run options honoured lane by lane (energy
// checks at every sample, no free flight skipped); invalid options fail every lane as simulate()
// does. (KR-α's half-step energy does not grow on the rod, so no lane stops on the bound: the
// loop that stops lanes is core/batch/batch_lanes.hpp's, shared with the kernels whose tests do.)
TEST(BatchedKrAlpha, PartialBatchesAndRunOptions) {
  expect_batch_equals_scalar({{"alone", RodScene{}, KrAlphaParams{}}});
  RodScene late;
  late.gap = 0.2;
  late.t_end = 1e-3;
  RodScene gap0;
  gap0.gap = 0.0;
  const std::vector<LaneRun> runs = {
      {"default", RodScene{}, KrAlphaParams{}},
      {"late, rho_inf 1", late, KrAlphaParams{.rho_inf = 1.0}},
      {"gap 0, rho_inf 0", gap0, KrAlphaParams{.rho_inf = 0.0}},
  };
  expect_batch_equals_scalar(runs,
                             RunOptions{.energy_check_interval = 50, .skip_free_flight = false});
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);
}

TEST(BatchedKrAlpha, WhatMayShareABatch) {
  const RunOptions options;
  EXPECT_TRUE(kr_alpha_batchable(RodScene{}, KrAlphaParams{}));
  EXPECT_FALSE(kr_alpha_batchable(RodScene{}, HhtParams{}));
  EXPECT_TRUE(batchable(RodScene{}, KrAlphaParams{.rho_inf = 0.3}, options));
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  EXPECT_TRUE(batchable(consistent, KrAlphaParams{}, options));
  EXPECT_TRUE(same_batch(RodScene{}, KrAlphaParams{}, options, RodScene{},
                         KrAlphaParams{.rho_inf = 1.0}, options));
  // KR-α's batch steps KR-α only: step_kind() alone would put it with the single-step methods.
  EXPECT_FALSE(same_batch(RodScene{}, KrAlphaParams{}, options, RodScene{}, HhtParams{}, options));
  EXPECT_FALSE(same_batch(RodScene{}, HhtParams{}, options, RodScene{}, KrAlphaParams{}, options));
  EXPECT_FALSE(same_batch(RodScene{}, KrAlphaParams{}, options, RodScene{},
                          CentralDifferenceParams{}, options));
  RodScene other_dt;
  other_dt.courant = 0.4;
  EXPECT_FALSE(
      same_batch(RodScene{}, KrAlphaParams{}, options, other_dt, KrAlphaParams{}, options));
  // Damping, histories, a far wall and the other contact laws stay on the scalar path.
  RodScene damped;
  damped.rayleigh_mass = 200.0;
  EXPECT_FALSE(batchable(damped, KrAlphaParams{}, options));
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  EXPECT_FALSE(batchable(stiffness_damped, KrAlphaParams{}, options));
  EXPECT_FALSE(batchable(RodScene{}, KrAlphaParams{}, RunOptions{.record_history = true}));
  RodScene two_walls;
  two_walls.far_gap = 0.1;
  EXPECT_FALSE(batchable(two_walls, KrAlphaParams{}, options));
  RunOptions augmented;
  augmented.contact.law = ContactLaw::augmented_lagrangian;
  EXPECT_FALSE(batchable(RodScene{}, KrAlphaParams{}, augmented));
}

}  // namespace
}  // namespace impactid
