// simulate_chain_batch(): on scenes of several bodies every lane gives simulate()'s numbers bit
// for bit (issue 18: batched lanes bit-identical to simulate on multi-body scenes), whatever the
// other lanes do; and which runs may share a batch.
#include "core/batch/batched_chain.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "same_run.hpp"

namespace impactid {
namespace {

using testing::expect_same_run;

struct LaneRun {
  std::string name;
  Scene scene;
  MethodParams method;
};

// Runs `runs` as one batch and each alone through simulate(), and compares everything. Returns
// the scalar summaries, so that callers can check that the batch covers what it claims.
std::vector<RunSummary> expect_batch_equals_scalar(const std::vector<LaneRun>& runs,
                                                   const RunOptions& options = {}) {
  std::vector<AssembledScene> assembled;
  std::vector<MethodParams> methods;
  for (const LaneRun& r : runs) {
    assembled.push_back(assemble(r.scene));
    methods.push_back(r.method);
  }
  std::vector<const AssembledScene*> scenes;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    EXPECT_TRUE(chain_batchable(assembled[k], methods[k], options)) << runs[k].name;
    EXPECT_TRUE(same_chain_batch(assembled[0], options, assembled[k], options)) << runs[k].name;
    scenes.push_back(&assembled[k]);
  }
  ChainBatchWorkspace batch;
  std::vector<RunSummary> batched(runs.size());
  simulate_chain_batch(scenes, methods, options, batch, batched);

  std::vector<RunSummary> scalars;
  SimulationWorkspace ws;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string& name = runs[k].name;
    const RunSummary s = simulate(assembled[k], methods[k], options, ws);
    expect_same_run(batched[k], batch.traces[k], s, ws.trace, name);
    scalars.push_back(s);
  }
  return scalars;
}

Segment segment(double length, int elements, double area = 1.0) {
  return Segment{.length = length, .elements = elements, .area = area};
}

// A striker, a stepped bar and a third body between two walls: four contacts, two of them
// between bodies, one body touched on both ends, segments of different sizes.
Scene chain() {
  Scene s;
  s.bodies.push_back(Body{.name = "striker", .velocity = -1000.0, .segments = {segment(10, 20)}});
  s.bodies.push_back(
      Body{.name = "bar", .gap = 0.01, .segments = {segment(15, 30), segment(15, 24, 4.0)}});
  s.bodies.push_back(
      Body{.name = "third", .velocity = -300.0, .gap = 0.005, .segments = {segment(8, 16, 2.0)}});
  s.left_wall = Wall{.gap = 0.02};  // the striker hits it, rebounds and hits the bar
  s.right_wall = Wall{.gap = 0.01};
  s.t_end = 3e-4;
  return s;
}

// A full batch: every implicit method, an unstable lane, lanes with other gaps and velocities
// (so other free flights, first contacts and step counts), a lane that ends early.
TEST(BatchedChain, EveryLaneEqualsTheScalarRunBitForBit) {
  const Scene base = chain();
  Scene wide = base;
  wide.bodies[2].gap = 0.05;
  wide.left_wall->gap = 0.05;
  Scene touching = base;
  touching.bodies[2].gap = 0.0;
  touching.left_wall->gap = 0.0;
  Scene slow = base;
  slow.bodies[0].velocity = -200.0;
  Scene short_run = base;
  short_run.t_end = 3e-5;
  Scene away = base;
  away.bodies[0].velocity = 400.0;
  away.bodies[2].velocity = 400.0;
  const std::vector<LaneRun> runs = {
      {"hht", base, HhtParams{.alpha = -0.3}},
      {"hht unstable", base, HhtParams{.alpha = -0.5, .delta = 0.0}},
      {"generalized-alpha (alpha_m != 0)", base, GeneralizedAlphaParams{.rho_inf = 0.6}},
      {"newmark, wide gap", wide, NewmarkParams{.delta = 0.3}},
      {"backward-euler, slow", slow, BackwardEulerParams{}},
      {"hht weighted", base, HhtParams{.alpha = -0.1, .contact = ContactWeighting::weighted}},
      {"newmark beta-gamma, touching", touching,
       NewmarkParams{.coefficients = BetaGamma{0.3025, 0.6}}},
      {"generalized-alpha weighted", base,
       GeneralizedAlphaParams{.rho_inf = 0.5, .contact = ContactWeighting::weighted}},
      {"trapezoidal", base, NewmarkParams{.delta = 0.0}},
      {"hht eq. 19", base, HhtParams{.alpha = -0.5, .delta = 0.75}},
      {"newmark, short run", short_run, NewmarkParams{.delta = 1.0}},
      {"hht, bodies moving apart", away, HhtParams{.alpha = -0.2}},
      {"backward-euler", base, BackwardEulerParams{}},
      {"generalized-alpha rho_inf 0", base, GeneralizedAlphaParams{.rho_inf = 0.0}},
      {"hht alpha 0, touching", touching, HhtParams{.alpha = 0.0, .delta = 0.2}},
      {"newmark", base, NewmarkParams{.delta = 0.5}},
  };
  ASSERT_EQ(runs.size(), static_cast<std::size_t>(kBatchLanes));
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  // The batch covers what it claims: one lane stops early while the others run on, lanes start
  // at different samples, and the contacts close.
  EXPECT_EQ(scalar[1].status, RunStatus::unstable);
  EXPECT_LT(scalar[1].steps, scalar[0].steps);
  EXPECT_EQ(scalar[0].status, RunStatus::ok);
  EXPECT_NE(scalar[3].skipped_steps, scalar[0].skipped_steps);
  EXPECT_EQ(scalar[6].skipped_steps, 0);
  EXPECT_LT(scalar[10].planned_steps, scalar[0].planned_steps);
  SimulationWorkspace ws;
  simulate(assemble(base), runs[0].method, RunOptions{}, ws);
  int pushed = 0;
  for (const std::vector<double>& p : ws.trace.contact_pressure) {
    pushed += *std::max_element(p.begin(), p.end()) > 0.0 ? 1 : 0;
  }
  EXPECT_GE(pushed, 3);
}

// One contact between two bodies (the kernel's one-contact path, as in the shipped two-rods and
// hopkinson plans): a full batch of HHT and generalized-α lanes with gaps and velocities that
// differ, so lanes close the contact at different samples.
TEST(BatchedChain, OneContactBetweenTwoBodies) {
  Scene s;
  s.bodies.push_back(Body{.name = "striker", .velocity = 1000.0, .segments = {segment(10, 50)}});
  s.bodies.push_back(Body{.name = "bar", .gap = 0.01, .segments = {segment(30, 150)}});
  std::vector<LaneRun> runs;
  for (int l = 0; l < kBatchLanes; ++l) {
    Scene lane = s;
    lane.bodies[1].gap = 0.01 * (1 + l % 3);
    lane.bodies[0].velocity = 1000.0 - 100.0 * (l % 4);
    const MethodParams method = l % 2 == 0
                                    ? MethodParams{HhtParams{.alpha = -0.03 * l}}
                                    : MethodParams{GeneralizedAlphaParams{.rho_inf = 0.06 * l}};
    runs.push_back({"lane " + std::to_string(l), lane, method});
  }
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  EXPECT_EQ(scalar[5].status, RunStatus::ok) << scalar[5].message;
}

// At a small Courant number a contact's column A⁻¹·G_kᵀ decays fast enough along a long body to
// underflow to exact zeros, at a row that depends on the method's β: lanes then correct
// different rows, and the kernel must touch each lane's own rows only.
TEST(BatchedChain, ColumnsThatUnderflowAtDifferentRowsPerLane) {
  Scene s;
  s.bodies.push_back(Body{.name = "striker", .velocity = 1000.0, .segments = {segment(30, 300)}});
  s.bodies.push_back(Body{.name = "target", .gap = 0.002, .segments = {segment(30, 300)}});
  s.courant = 0.05;
  s.t_end = 1e-5;
  const std::vector<LaneRun> runs = {
      {"newmark delta 0", s, NewmarkParams{.delta = 0.0}},
      {"newmark delta 0.5", s, NewmarkParams{.delta = 0.5}},
      {"backward-euler", s, BackwardEulerParams{}},
  };
  // The premise: the lanes' columns end at different rows.
  const AssembledScene a = assemble(s);
  ImplicitIntegrator first, second;
  ASSERT_TRUE(first.initialize(a.system, implicit_coefficients(runs[0].method), a.dt));
  ASSERT_TRUE(second.initialize(a.system, implicit_coefficients(runs[2].method), a.dt));
  ASSERT_NE(first.constraint_rows()[0], second.constraint_rows()[0]);
  ASSERT_LT(first.constraint_rows()[0].second - first.constraint_rows()[0].first, 300);
  const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
  EXPECT_EQ(scalar[0].status, RunStatus::ok);
}

// Damping (C terms in the predictor and the right-hand side, no rigid free flight with
// mass-proportional damping) and a consistent mass; partial batches.
TEST(BatchedChain, DampedAndConsistentMassScenesToo) {
  Scene damped = chain();
  damped.rayleigh_mass = 2000.0;
  damped.rayleigh_stiffness = 1e-8;
  Scene consistent = chain();
  consistent.mass = MassMatrix::consistent;
  for (const Scene& s : {damped, consistent}) {
    const std::vector<LaneRun> runs = {
        {"hht", s, HhtParams{.alpha = -0.2}},
        {"generalized-alpha", s, GeneralizedAlphaParams{.rho_inf = 0.8}},
        {"newmark", s, NewmarkParams{.delta = 0.1}},
    };
    const std::vector<RunSummary> scalar = expect_batch_equals_scalar(runs);
    EXPECT_EQ(scalar[0].status, RunStatus::ok) << scalar[0].message;
  }
}

TEST(BatchedChain, WhatMayShareABatch) {
  const Scene s = chain();
  const AssembledScene a = assemble(s);
  const RunOptions options;
  EXPECT_TRUE(chain_batchable(a, HhtParams{}, options));
  EXPECT_FALSE(chain_batchable(a, CentralDifferenceParams{}, options));
  EXPECT_FALSE(chain_batchable(a, HhtParams{}, RunOptions{.record_history = true}));
  // The paper's form runs on the rod's named contact, which this kernel does not know.
  Scene paper;
  paper.bodies.push_back(Body{.name = "rod", .segments = {segment(20, 100)}});
  paper.bodies[0].velocity = 1000.0;
  paper.right_wall = Wall{.gap = 0.01};
  EXPECT_FALSE(chain_batchable(assemble(paper), HhtParams{}, options));

  // Gaps, velocities and the end time are per lane; the bodies' matrices and the step are not.
  Scene other = s;
  other.bodies[1].gap = 0.3;
  other.bodies[0].velocity = 10.0;
  other.t_end = 1e-4;
  EXPECT_TRUE(same_chain_batch(a, options, assemble(other), options));
  other = s;
  other.bodies[1].segments[1].area = 3.0;
  EXPECT_FALSE(same_chain_batch(a, options, assemble(other), options));
  other = s;
  other.courant = 0.4;
  EXPECT_FALSE(same_chain_batch(a, options, assemble(other), options));
  other = s;
  other.rayleigh_stiffness = 1e-8;
  EXPECT_FALSE(same_chain_batch(a, options, assemble(other), options));
  EXPECT_FALSE(same_chain_batch(a, options, a, RunOptions{.energy_check_interval = 4}));
}

}  // namespace
}  // namespace impactid
