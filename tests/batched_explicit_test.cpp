// The explicit methods on the rod's batched kernel (core/batch/batched_explicit.hpp): every lane
// gives simulate()'s numbers bit for bit, whatever the other lanes do (a lane that goes unstable
// among stable ones, lanes that start and end at other samples, batches smaller than kBatchLanes);
// and which runs may share a batch.
#include "core/batch/batched_explicit.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "batched_runs.hpp"
#include "core/batch/batched_simulation.hpp"

namespace impactid {
namespace {

using testing::expect_batch_equals_scalar;
using testing::LaneRun;

constexpr CentralDifferenceParams kCentral{};
constexpr CentralDifferenceParams kBackward{.velocity = CdmVelocity::backward};

// Scenes of one rod and time step that differ in everything a lane may have of its own: gap (so
// the free flight, the impact and the number of steps), velocity, end time.
std::vector<LaneRun> mixed_lanes(const RodScene& base, const std::string& what) {
  const auto scene = [&](double gap, double velocity, std::optional<double> t_end) {
    RodScene s = base;
    s.gap = gap;
    s.velocity = velocity;
    s.t_end = t_end;
    return s;
  };
  return {
      {what + " default", base, kCentral},
      {what + " backward", base, kBackward},
      {what + " gap 0.2", scene(0.2, 1000.0, {}), kCentral},
      {what + " gap 0 (no free flight)", scene(0.0, 1000.0, {}), kBackward},
      {what + " slow", scene(0.05, 300.0, {}), kCentral},
      {what + " fast", scene(0.01, 5000.0, {}), kCentral},
      {what + " short run", scene(0.01, 1000.0, 2e-4), kBackward},
      {what + " moving away", scene(0.01, -500.0, {}), kCentral},
      {what + " gap 0.1 backward", scene(0.1, 700.0, 1.5e-3), kBackward},
      {what + " gap 0.03", scene(0.03, 2000.0, {}), kCentral},
      {what + " end 5e-4", scene(0.0, 1500.0, 5e-4), kCentral},
      {what + " slow backward", scene(0.02, 100.0, {}), kBackward},
      {what + " gap 0.15", scene(0.15, 1000.0, 1e-3), kCentral},
      {what + " gap 0.001", scene(0.001, 1000.0, {}), kBackward},
      {what + " fast backward", scene(0.05, 3000.0, {}), kBackward},
      {what + " at rest", scene(0.01, 0.0, 3e-4), kCentral},
  };
}

// Full batches at Courant numbers below the limit, at it (the magic time step, where the energy
// is central difference's own) and on a consistent mass (no limit certified: the plain energy).
TEST(BatchedExplicit, CentralDifferenceLanesEqualTheScalarRunBitForBit) {
  for (const double courant : {0.5, 1.0, 0.3}) {
    RodScene base;
    base.courant = courant;
    const std::string what = "courant " + std::to_string(courant);
    const std::vector<LaneRun> runs = mixed_lanes(base, what);
    ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
    const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
    // The batch covers what it claims: lanes start and end at different samples, every lane
    // runs to its end, and the contact is reached (λ > 0 somewhere).
    EXPECT_EQ(scalar[0].status, RunStatus::ok) << what << ": " << scalar[0].message;
    EXPECT_NE(scalar[2].skipped_steps, scalar[0].skipped_steps) << what;
    EXPECT_NE(scalar[2].planned_steps, scalar[0].planned_steps) << what;
    EXPECT_EQ(scalar[3].skipped_steps, 0) << what;
    EXPECT_LT(scalar[6].planned_steps, scalar[0].planned_steps) << what;
    EXPECT_GT(scalar[0].stable_dt, 0.0) << what;
  }
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  consistent.courant = 0.5;  // within 1/√3, its limit; none is certified for a consistent mass
  const std::vector<RunSummary> scalar =
      expect_batch_equals_scalar(mixed_lanes(consistent, "consistent"));
  EXPECT_EQ(scalar[0].status, RunStatus::ok) << scalar[0].message;
  EXPECT_EQ(scalar[0].stable_dt, 0.0);
}

// Above the limit the runs go unstable (central difference is conditionally stable): each lane
// stops at the sample its scalar run stops at, and is zeroed, while lanes that never excite the
// growing mode (a rigid motion away from the wall) or end first run on to their end.
TEST(BatchedExplicit, ALaneAboveItsStableStepStopsAsTheScalarRun) {
  for (const double courant : {1.0001, 1.01, 1.2}) {
    RodScene base;
    base.courant = courant;
    const std::string what = "courant " + std::to_string(courant);
    const std::vector<RunSummary> scalar = expect_batch_equals_scalar(mixed_lanes(base, what));
    EXPECT_EQ(scalar[0].status, RunStatus::unstable) << what;
    EXPECT_LT(scalar[0].steps, scalar[0].planned_steps) << what;
    EXPECT_EQ(scalar[7].status, RunStatus::ok) << what << ": " << scalar[7].message;
    EXPECT_EQ(scalar[7].steps, scalar[7].planned_steps) << what;
  }
}

// Fewer runs than lanes; a lane that starts after the others have stopped; run options
// honoured lane by lane; invalid options fail every lane as simulate() does.
TEST(BatchedExplicit, PartialBatchesAndRunOptions) {
  RodScene late;
  late.gap = 0.2;
  late.t_end = 1e-3;
  RodScene unstable;
  unstable.courant = 1.2;
  RodScene unstable_late = late;
  unstable_late.courant = 1.2;
  expect_batch_equals_scalar({{"alone", RodScene{}, kCentral}});
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar({
      {"unstable", unstable, kCentral},
      {"unstable, late", unstable_late, kBackward},
  });
  EXPECT_EQ(scalar[0].status, RunStatus::unstable);
  EXPECT_EQ(scalar[1].status, RunStatus::unstable);
  EXPECT_LT(scalar[0].steps, scalar[1].skipped_steps)
      << "the first lane ends before the second starts";

  const std::vector<LaneRun> runs = {
      {"cdm", RodScene{}, kCentral},
      {"cdm backward, late", late, kBackward},
      {"cdm, gap 0",
       [] {
         RodScene s;
         s.gap = 0.0;
         return s;
       }(),
       kCentral},
  };
  expect_batch_equals_scalar(runs,
                             RunOptions{.energy_check_interval = 50, .skip_free_flight = false});
  expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 1});
  expect_batch_equals_scalar(runs, RunOptions{.energy_growth_limit = 1.0001});
  const std::vector<RunSummary> failed =
      expect_batch_equals_scalar(runs, RunOptions{.energy_check_interval = 0});
  EXPECT_EQ(failed[0].status, RunStatus::failed);

  // No energy bound to speak of: a lane whose values overflow stops at the first non-finite
  // sample, between energy checks, while a lane moving away rigidly runs on.
  RodScene coarse;
  coarse.courant = 1.5;
  RodScene coarse_away = coarse;
  coarse_away.velocity = -100.0;
  const std::vector<RunSummary> overflow = expect_batch_equals_scalar(
      {{"cdm, overflows", coarse, kCentral},
       {"cdm backward, overflows", coarse, kBackward},
       {"cdm, away", coarse_away, kCentral}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
  EXPECT_EQ(overflow[0].status, RunStatus::unstable);
  EXPECT_NE(overflow[0].message.find("non-finite"), std::string::npos) << overflow[0].message;
  EXPECT_EQ(overflow[2].status, RunStatus::ok) << overflow[2].message;
}

// The Noh–Bathe explicit scheme (two explicit sub-steps, the contact a forward increment at each,
// and one at the start): full batches of lanes with their own p, gap, velocity and end time,
// below its stable step, on a consistent mass, and above the step for some lanes.
std::vector<LaneRun> noh_bathe_lanes(const RodScene& base, const std::string& what) {
  std::vector<LaneRun> runs = mixed_lanes(base, what);
  const double ps[] = {0.54, 0.5,  0.6,  0.75, 0.9, 0.54, 0.7,  0.55,
                       0.8,  0.65, 0.54, 0.95, 0.5, 0.58, 0.85, 0.54};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    runs[k].method = NohBatheParams{.p = ps[k]};
    runs[k].name = runs[k].name + ", p " + std::to_string(ps[k]);
  }
  return runs;
}

TEST(BatchedExplicit, NohBatheLanesEqualTheScalarRunBitForBit) {
  for (const double courant : {0.5, 1.0, 1.5}) {
    RodScene base;
    base.courant = courant;
    const std::string what = "noh-bathe courant " + std::to_string(courant);
    const std::vector<RunSummary> scalar = expect_batch_equals_scalar(noh_bathe_lanes(base, what));
    EXPECT_EQ(scalar[0].status, RunStatus::ok) << what << ": " << scalar[0].message;
    EXPECT_NE(scalar[2].skipped_steps, scalar[0].skipped_steps) << what;
    EXPECT_EQ(scalar[3].skipped_steps, 0) << what;
  }
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  consistent.courant = 0.4;
  expect_batch_equals_scalar(noh_bathe_lanes(consistent, "noh-bathe consistent"));
  // Lanes in contact at the start (gap 0: the start's multiplier corrects a₀) before lanes of
  // the same velocity, which start from the uncorrected a₀ (found by a sweep of p at gap 0).
  RodScene touching;
  touching.gap = 0.0;
  touching.velocity = 300.0;
  touching.courant = 0.25;
  RodScene free = touching;
  free.gap = 0.01;
  expect_batch_equals_scalar({{"noh-bathe gap 0, p 0.5", touching, NohBatheParams{.p = 0.5}},
                              {"noh-bathe gap 0, p 0.55", touching, NohBatheParams{.p = 0.55}},
                              {"noh-bathe gap 0.01, p 0.6", free, NohBatheParams{.p = 0.6}}});
}

TEST(BatchedExplicit, NohBatheLanesAboveTheirStableStepStopAsTheScalarRun) {
  RodScene base;
  base.courant = 1.9;
  const std::vector<RunSummary> scalar =
      expect_batch_equals_scalar(noh_bathe_lanes(base, "noh-bathe courant 1.9"));
  int unstable = 0, ok = 0;
  for (const RunSummary& s : scalar) {
    unstable += s.status == RunStatus::unstable;
    ok += s.status == RunStatus::ok;
  }
  EXPECT_GT(unstable, 0);
  EXPECT_GT(ok, 0);
  expect_batch_equals_scalar({{"noh-bathe alone", RodScene{}, NohBatheParams{}},
                              {"noh-bathe p 0.9", RodScene{}, NohBatheParams{.p = 0.9}}},
                             RunOptions{.energy_check_interval = 1});
  RodScene coarse;
  coarse.courant = 3.0;
  const std::vector<RunSummary> overflow = expect_batch_equals_scalar(
      {{"noh-bathe, overflows", coarse, NohBatheParams{}},
       {"noh-bathe p 0.6, overflows", coarse, NohBatheParams{.p = 0.6}}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
  EXPECT_EQ(overflow[0].status, RunStatus::unstable);
}

// Kim's two-stage explicit scheme (two explicit stages, the contact a forward increment at each:
// ũ₁ at stage 1, the sample and the next force point at stage 2; one at the start): full batches
// of lanes with their own p (⅓ and ½ among them: at ½ the sample's own problem is not solved),
// gap, velocity and end time, below its stable step, on a consistent mass, and above the step
// for some lanes.
std::vector<LaneRun> kim_lanes(const RodScene& base, const std::string& what) {
  std::vector<LaneRun> runs = mixed_lanes(base, what);
  const double ps[] = {0.5,  1.0 / 3.0, 0.4, 0.45, 0.35, 0.5,  0.42, 0.3611,
                       0.48, 0.4418,    0.5, 0.34, 0.47, 0.39, 0.5,  0.44};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    runs[k].method = KimExplicitParams{.p = ps[k]};
    runs[k].name = runs[k].name + ", p " + std::to_string(ps[k]);
  }
  return runs;
}

TEST(BatchedExplicit, KimLanesEqualTheScalarRunBitForBit) {
  for (const double courant : {0.5, 1.0, 1.2}) {
    RodScene base;
    base.courant = courant;
    const std::string what = "kim courant " + std::to_string(courant);
    const std::vector<LaneRun> runs = kim_lanes(base, what);
    ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
    const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
    // The batch covers what it claims: lanes start and end at different samples, and both
    // contact problems of stage 2 are met (λ > 0 at p = ½ and at p < ½).
    EXPECT_EQ(scalar[0].status, RunStatus::ok) << what << ": " << scalar[0].message;
    EXPECT_EQ(scalar[1].status, RunStatus::ok) << what << ": " << scalar[1].message;
    EXPECT_NE(scalar[2].skipped_steps, scalar[0].skipped_steps) << what;
    EXPECT_EQ(scalar[3].skipped_steps, 0) << what;
    EXPECT_LT(scalar[6].planned_steps, scalar[0].planned_steps) << what;
    EXPECT_GT(scalar[0].stable_dt, 0.0) << what;
  }
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  consistent.courant = 0.4;
  expect_batch_equals_scalar(kim_lanes(consistent, "kim consistent"));
  // Lanes in contact at the start (gap 0: the start's multiplier corrects a₀) before lanes of
  // the same velocity, which start from the uncorrected a₀.
  RodScene touching;
  touching.gap = 0.0;
  touching.velocity = 300.0;
  touching.courant = 0.25;
  RodScene free = touching;
  free.gap = 0.01;
  expect_batch_equals_scalar({{"kim gap 0, p 0.5", touching, KimExplicitParams{.p = 0.5}},
                              {"kim gap 0, p 0.4", touching, KimExplicitParams{.p = 0.4}},
                              {"kim gap 0.01, p 1/3", free, KimExplicitParams{.p = 1.0 / 3.0}}});
}

// Above Ω_crit(p)/2 (1.22 at p = ⅓ and ½, 1.54 at 0.4418) lanes go unstable among lanes that
// stay stable; a batch smaller than kBatchLanes; energy checks at every sample; overflow between
// checks.
TEST(BatchedExplicit, KimLanesAboveTheirStableStepStopAsTheScalarRun) {
  RodScene base;
  base.courant = 1.4;
  const std::vector<RunSummary> scalar =
      expect_batch_equals_scalar(kim_lanes(base, "kim courant 1.4"));
  int unstable = 0, ok = 0;
  for (const RunSummary& s : scalar) {
    unstable += s.status == RunStatus::unstable;
    ok += s.status == RunStatus::ok;
  }
  EXPECT_GT(unstable, 0);
  EXPECT_GT(ok, 0);
  EXPECT_FALSE(scalar[0].warning.empty());
  expect_batch_equals_scalar({{"kim alone", RodScene{}, KimExplicitParams{}},
                              {"kim p 1/3", RodScene{}, KimExplicitParams{.p = 1.0 / 3.0}}},
                             RunOptions{.energy_check_interval = 1});
  RodScene coarse;
  coarse.courant = 3.0;
  const std::vector<RunSummary> overflow = expect_batch_equals_scalar(
      {{"kim, overflows", coarse, KimExplicitParams{}},
       {"kim p 0.4, overflows", coarse, KimExplicitParams{.p = 0.4}}},
      RunOptions{.energy_growth_limit = 1e300, .energy_check_interval = 100'000});
  EXPECT_EQ(overflow[0].status, RunStatus::unstable);
}

TEST(BatchedExplicit, WhatMayShareABatch) {
  const RunOptions options;
  EXPECT_EQ(explicit_batch_kind(kCentral), ExplicitBatchKind::central_difference);
  EXPECT_EQ(explicit_batch_kind(NohBatheParams{}), ExplicitBatchKind::noh_bathe);
  EXPECT_EQ(explicit_batch_kind(KimExplicitParams{}), ExplicitBatchKind::kim_explicit);
  EXPECT_TRUE(batchable(RodScene{}, KimExplicitParams{.p = 0.4}, options));
  EXPECT_FALSE(
      same_batch(RodScene{}, NohBatheParams{}, options, RodScene{}, KimExplicitParams{}, options));
  EXPECT_TRUE(same_batch(RodScene{}, KimExplicitParams{}, options, RodScene{},
                         KimExplicitParams{.p = 1.0 / 3.0}, options));
  EXPECT_EQ(explicit_batch_kind(HhtParams{}), ExplicitBatchKind::none);
  EXPECT_TRUE(batchable(RodScene{}, NohBatheParams{.p = 0.7}, options));
  EXPECT_FALSE(same_batch(RodScene{}, kCentral, options, RodScene{}, NohBatheParams{}, options));
  EXPECT_TRUE(same_batch(RodScene{}, NohBatheParams{}, options, RodScene{},
                         NohBatheParams{.p = 0.9}, options));
  EXPECT_TRUE(batchable(RodScene{}, kCentral, options));
  EXPECT_TRUE(batchable(RodScene{}, kBackward, options));
  RodScene consistent;
  consistent.mass = MassMatrix::consistent;
  EXPECT_TRUE(batchable(consistent, kCentral, options));
  // Damping stays on the scalar path; so do histories, a far wall and the other contact laws.
  RodScene damped;
  damped.rayleigh_mass = 200.0;
  EXPECT_FALSE(batchable(damped, kCentral, options));
  RodScene stiffness_damped;
  stiffness_damped.rayleigh_stiffness = 2e-8;
  EXPECT_FALSE(batchable(stiffness_damped, kBackward, options));
  EXPECT_FALSE(batchable(RodScene{}, kCentral, RunOptions{.record_history = true}));
  RodScene two_walls;
  two_walls.far_gap = 0.1;
  EXPECT_FALSE(batchable(two_walls, kCentral, options));
  for (const ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    RunOptions penalty;
    penalty.contact.law = law;
    EXPECT_FALSE(batchable(RodScene{}, kCentral, penalty)) << to_string(law);
  }

  // A batch steps one method: central difference's lanes (either velocity variant, each its own
  // gap, velocity and end time), not mixed with the implicit or composite ones.
  RodScene other_gap;
  other_gap.gap = 0.3;
  other_gap.velocity = 10.0;
  other_gap.t_end = 1e-3;
  EXPECT_TRUE(same_batch(RodScene{}, kCentral, options, other_gap, kBackward, options));
  EXPECT_FALSE(same_batch(RodScene{}, kCentral, options, RodScene{}, HhtParams{}, options));
  EXPECT_FALSE(same_batch(RodScene{}, HhtParams{}, options, RodScene{}, kCentral, options));
  EXPECT_FALSE(same_batch(RodScene{}, kCentral, options, RodScene{}, BatheParams{}, options));
  RodScene other_dt;
  other_dt.courant = 0.4;
  EXPECT_FALSE(same_batch(RodScene{}, kCentral, options, other_dt, kCentral, options));
}

}  // namespace
}  // namespace impactid
