// Paoli–Schatzman's impact law (core/contact/paoli_schatzman_law.hpp) on central difference: a free
// mass leaves the wall at −e times its speed, on each of the stepper's contact paths (one wall,
// two walls, a constraint list, a sparse model); on the paper's rod the weighted mean
// (u_{n+1} + e·u_{n−1})/(1 + e) of the contact DOF never passes the wall and sits on it whenever
// λ_n > 0, with λ >= 0; e = 0 is Lagrange's law bit for bit; the methods without a two-step
// recurrence refuse the law by name, and so does a massless contact DOF with e > 0.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "batched_runs.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/contact/paoli_schatzman_law.hpp"
#include "core/methods/central_difference.hpp"
#include "core/methods/method_registry.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/run/simulation.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

constexpr double kDt = 1e-3;
constexpr double kSpeed0 = 3.0, kSpeed1 = -2.0;   // [mm/s] of DOF 0 and DOF 1, toward their walls
constexpr double kGap0 = 0.0512, kGap1 = 0.0437;  // [mm]: impacts between two steps

ContactPenalties paoli_schatzman(double e) {
  return ContactPenalties{.law = ContactLaw::lagrange, .restitution = e};
}

// Two free masses (no stiffness) with a lumped mass of 2: DOF 0 moves toward a wall at +kGap0,
// DOF 1 toward one at −kGap1. `listed`: the walls as a constraint list; otherwise DOF 0's is the
// named wall and DOF 1's the named far wall.
SecondOrderSystem two_free_masses(bool listed) {
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(2);
  system.mass.diag.setConstant(2.0);
  system.damping = Tridiagonal::zero(2);
  system.stiffness = Tridiagonal::zero(2);
  if (listed) {
    system.constraints = {Constraint{.plus = 0, .minus = -1, .gap = kGap0},
                          Constraint{.plus = -1, .minus = 1, .gap = kGap1}};
  } else {
    system.contact_dof = 0;
    system.gap = kGap0;
    system.far_contact_dof = 1;
    system.far_gap = kGap1;
  }
  return system;
}

State moving_toward_the_walls() {
  State s = testing::make_state(Eigen::VectorXd::Zero(2), Eigen::Vector2d(kSpeed0, kSpeed1));
  s.a = Eigen::VectorXd::Zero(2);
  return s;
}

// The velocities after 200 steps, well past both impacts (about 17 and 22 steps in).
template <class Stepper, class System>
Eigen::VectorXd velocity_after_the_impacts(Stepper& cdm, const System& system, double e,
                                           State at_t) {
  EXPECT_TRUE(cdm.initialize(system, CdmVelocity::central, kDt, at_t, paoli_schatzman(e)))
      << cdm.failure();
  for (int i = 0; i < 200; ++i) {
    cdm.step(system, at_t);
    EXPECT_GE(at_t.lambda, 0.0);
    for (Eigen::Index j = 0; j < at_t.multipliers.size(); ++j) EXPECT_GE(at_t.multipliers[j], 0.0);
  }
  return at_t.v;
}

TEST(PaoliSchatzman, AFreeMassLeavesTheWallAtMinusETimesItsSpeedOnEveryPath) {
  for (const double e : {0.0, 0.3, 0.7, 1.0}) {
    for (const bool listed : {false, true}) {
      const SecondOrderSystem system = two_free_masses(listed);
      CentralDifference cdm;
      State start = moving_toward_the_walls();
      if (listed) start.multipliers = Eigen::VectorXd::Zero(2);
      const Eigen::VectorXd v = velocity_after_the_impacts(cdm, system, e, start);
      EXPECT_NEAR(v[0], -e * kSpeed0, 1e-9) << "e = " << e << (listed ? ", listed" : ", walls");
      EXPECT_NEAR(v[1], -e * kSpeed1, 1e-9) << "e = " << e << (listed ? ", listed" : ", walls");
    }
    // The same two masses on a sparse model.
    SparseSystem sparse;
    sparse.mass = SparseMatrix(2, 2);
    sparse.mass.insert(0, 0) = 2.0;
    sparse.mass.insert(1, 1) = 2.0;
    sparse.stiffness = SparseMatrix(2, 2);
    sparse.damping = SparseMatrix(2, 2);
    sparse.mass.makeCompressed();
    sparse.constraints = two_free_masses(true).constraints;
    SparseCentralDifference cdm;
    State start = moving_toward_the_walls();
    start.multipliers = Eigen::VectorXd::Zero(2);
    const Eigen::VectorXd v = velocity_after_the_impacts(cdm, sparse, e, start);
    EXPECT_NEAR(v[0], -e * kSpeed0, 1e-9) << "e = " << e << ", sparse";
    EXPECT_NEAR(v[1], -e * kSpeed1, 1e-9) << "e = " << e << ", sparse";
  }
}

RunOptions with_restitution(double e) {
  RunOptions options = testing::stepping_options();
  options.contact = ContactTreatment{.law = ContactLaw::paoli_schatzman, .restitution = e};
  return options;
}

// On the paper's rod: λ_n >= 0; the mean (u_{n+1} + e·u_{n−1})/(1 + e) of the contact DOF is at
// most the gap, and on it (to rounding) where λ_n > 0; the contact DOF itself may pass the wall
// (a free mass by up to 2e/(1 + e) of a step's travel, at the worst phase of the impact).
TEST(PaoliSchatzman, TheMeanOfTheStepsAroundEachSampleHoldsTheGapOnThePapersRod) {
  const RodScene rod;
  for (const double e : {0.25, 0.5, 1.0}) {
    const testing::Run run = testing::run(rod, CentralDifferenceParams{}, with_restitution(e));
    ASSERT_EQ(run.summary.status, RunStatus::ok) << run.summary.message;
    const std::vector<double>& u = run.trace.displacement;
    const std::vector<double>& p = run.trace.pressure;
    ASSERT_EQ(u.size(), p.size());
    int pushed = 0;
    double deepest = 0.0;
    for (std::size_t n = 1; n + 1 < u.size(); ++n) {
      EXPECT_GE(p[n], 0.0) << "sample " << n;
      const double mean = (u[n + 1] + e * u[n - 1]) / (1.0 + e);
      EXPECT_LE(mean, rod.gap * (1.0 + 1e-12)) << "sample " << n << ", e = " << e;
      if (p[n] > 0.0) {
        ++pushed;
        EXPECT_NEAR(mean, rod.gap, 1e-12 * rod.gap) << "sample " << n << ", e = " << e;
      }
      deepest = std::max(deepest, u[n] - rod.gap);
    }
    EXPECT_GT(pushed, 10) << "e = " << e;
    EXPECT_GT(deepest, 0.0) << "e = " << e;  // the law lets u itself pass the wall, by O(Δt)
  }
}

TEST(PaoliSchatzman, AtZeroRestitutionItIsLagrangesLawBitForBit) {
  const RodScene rod;
  const testing::Run lagrange = testing::run(rod, CentralDifferenceParams{});
  const testing::Run zero = testing::run(rod, CentralDifferenceParams{}, with_restitution(0.0));
  EXPECT_EQ(zero.trace.pressure, lagrange.trace.pressure);
  EXPECT_EQ(zero.trace.velocity, lagrange.trace.velocity);
  EXPECT_EQ(zero.trace.displacement, lagrange.trace.displacement);
  const testing::Run half = testing::run(rod, CentralDifferenceParams{}, with_restitution(0.5));
  EXPECT_NE(half.trace.pressure, lagrange.trace.pressure);
}

// The rod's batched central difference shifts the gap as the scalar step does: 16 lanes of other
// gaps, speeds, end times and velocity variants, bit for bit as each alone. A batch steps one e.
TEST(PaoliSchatzman, BatchedCentralDifferenceLanesEqualTheScalarRunBitForBit) {
  RunOptions options;
  options.contact = ContactTreatment{.law = ContactLaw::paoli_schatzman, .restitution = 0.6};
  std::vector<testing::LaneRun> runs;
  for (int k = 0; k < kBatchLanes; ++k) {
    RodScene scene;
    scene.gap = 0.004 * (k + 1);
    scene.velocity = 800.0 + 25.0 * k;
    if (k % 3 == 2) scene.t_end = 6e-4;
    runs.push_back({"lane " + std::to_string(k), scene,
                    CentralDifferenceParams{.velocity = k % 2 ? CdmVelocity::backward
                                                              : CdmVelocity::central}});
  }
  const std::vector<RunSummary> scalar = testing::expect_batch_equals_scalar(runs, options);
  for (const RunSummary& s : scalar) EXPECT_EQ(s.status, RunStatus::ok) << s.message;
  // Lagrange's law is another run, and another batch; so is another e, or another method.
  SimulationWorkspace ws;
  const RunSummary lagrange = simulate(runs[0].scene, runs[0].method, RunOptions{}, ws);
  EXPECT_NE(lagrange.final_energy, scalar[0].final_energy);
  RunOptions other = options;
  other.contact.restitution = 0.5;
  EXPECT_FALSE(
      same_batch(runs[0].scene, runs[0].method, options, runs[0].scene, runs[0].method, other));
  EXPECT_FALSE(batchable(RodScene{}, HhtParams{}, options));
}

TEST(PaoliSchatzman, OnlyAMethodWithATwoStepRecurrenceTakesIt) {
  for (const MethodDescriptor& method : method_registry()) {
    const auto refusal = contact_law_refusal(method, ContactLaw::paoli_schatzman);
    EXPECT_EQ(!refusal, method.two_step_displacement) << method.name;
    EXPECT_FALSE(contact_law_refusal(method, ContactLaw::lagrange)) << method.name;
    if (!refusal) continue;
    EXPECT_NE(refusal->find(std::string("method ") + method.name +
                            " does not take contact law paoli-schatzman"),
              std::string::npos)
        << *refusal;
    EXPECT_NE(refusal->find("the methods that take it: cdm"), std::string::npos) << *refusal;
    // simulate() refuses it too, as a failed run that says why.
    SimulationWorkspace ws;
    const RunSummary summary = simulate(RodScene{}, method.defaults(), with_restitution(0.5), ws);
    EXPECT_EQ(summary.status, RunStatus::failed) << method.name;
    EXPECT_NE(summary.message.find("contact = paoli-schatzman"), std::string::npos)
        << summary.message;
  }
}

TEST(PaoliSchatzman, AMasslessContactDofRefusesARestitution) {
  RodScene rod;
  rod.mass = MassMatrix::redistributed;
  SimulationWorkspace ws;
  const RunSummary refused = simulate(rod, CentralDifferenceParams{}, with_restitution(0.5), ws);
  EXPECT_EQ(refused.status, RunStatus::failed);
  EXPECT_NE(refused.message.find("restitution is not defined on a massless contact DOF"),
            std::string::npos)
      << refused.message;
  const RunSummary lagrange = simulate(rod, CentralDifferenceParams{}, with_restitution(0.0), ws);
  EXPECT_EQ(lagrange.status, RunStatus::ok) << lagrange.message;
}

}  // namespace
}  // namespace impactid
