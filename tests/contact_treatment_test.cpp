// The contact laws (core/contact/contact_treatment.hpp): the penalty law holds at every sample and
// converges to the Lagrange solution at first order in 1/k; the augmented Lagrangian converges to
// it within its tolerance and counts its iterations; central difference's explicit penalty shrinks
// the stable step as the bound says, and a step above it is flagged, while KR-α's penalty, solved
// with its forward increment, stays stable whatever k and the step; several bodies and two walls
// keep λ >= 0 under every law; bad settings are refused by name.
#include "core/contact/contact_treatment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/model/scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

RunOptions with_contact(ContactTreatment contact) {
  RunOptions options = testing::stepping_options();
  options.contact = contact;
  return options;
}

// λ = k·max(0, u_c − gap) at every sample of the rod, k = factor·E·A/h.
TEST(ContactTreatment, PenaltyForceIsTheSpringsAtEverySample) {
  const RodScene scene;
  const double k_cc = scene.youngs_modulus * scene.area * scene.elements / scene.length;
  for (const auto& [name, method] :
       std::vector<std::pair<const char*, MethodParams>>{{"hht", HhtParams{}},
                                                         {"newmark", NewmarkParams{}},
                                                         {"bathe", BatheParams{}},
                                                         {"houbolt", HouboltParams{}},
                                                         {"cdm", CentralDifferenceParams{}}}) {
    const testing::Run r = testing::run(
        scene, method, with_contact({.law = ContactLaw::penalty, .penalty_factor = 3.0}));
    ASSERT_EQ(r.summary.status, RunStatus::ok) << name << r.summary.message;
    long active = 0;
    for (long i = 0; i < r.trace.size(); ++i) {
      const double lambda = r.trace.pressure[i] * scene.area;
      const double penetration = r.trace.displacement[i] - scene.gap;
      ASSERT_GE(lambda, 0.0) << name << " sample " << i;
      // Central difference's force at t is the spring of u_t; the implicit methods' the spring of
      // the step's end: both the sample's own displacement.
      EXPECT_NEAR(lambda, 3.0 * k_cc * std::max(0.0, penetration), 1e-9 * 3.0 * k_cc * 1e-3)
          << name << " sample " << i;
      active += lambda > 0.0;
    }
    EXPECT_GT(active, 300) << name;
    EXPECT_GT(r.summary.max_penetration, 0.0) << name;
  }
}

// The penalty solution approaches Lagrange's as 1/k: each decade of k divides the largest pressure
// difference by 10 (measured orders 0.93, 0.99, 1.00 from factor 100 on for HHT). KR-α's too: its
// springs are solved with the forward increment, λ = p/(d + 1/k) against Lagrange's p/d.
TEST(ContactTreatment, PenaltyConvergesToLagrangeAtFirstOrderInOneOverK) {
  const RodScene scene;
  for (const auto& [name, method] : std::vector<std::pair<const char*, MethodParams>>{
           {"hht", HhtParams{}}, {"kr-alpha", KrAlphaParams{}}}) {
    const testing::Run lagrange = testing::run(scene, method);
    std::vector<double> differences;
    for (double factor : {1e3, 1e4, 1e5}) {
      const testing::Run r = testing::run(
          scene, method, with_contact({.law = ContactLaw::penalty, .penalty_factor = factor}));
      ASSERT_EQ(r.summary.status, RunStatus::ok) << name;
      differences.push_back(testing::max_abs_difference(r.trace.pressure, lagrange.trace.pressure));
    }
    for (std::size_t i = 0; i + 1 < differences.size(); ++i) {
      EXPECT_NEAR(std::log10(differences[i] / differences[i + 1]), 1.0, 0.1) << name << " " << i;
    }
  }
}

// KR-α's penalty is the spring of the displacement its equilibrium's force moves: the multiplier
// reported with sample i is k·max(0, u_c − gap) of sample i + 1 (as its Lagrange multiplier holds
// that sample on the wall, core/methods/kr_alpha.hpp), λ >= 0. The spring is solved with the
// forward increment, so no step is too large for it: with k = 10⁴·K_cc (an explicit spring's stable
// Courant number would be √(2/(2 + 10⁴)) = 0.014) the runs at Courant 0.5 and 4, dissipative and
// not, are ok, with no stable step reported or warning, and the energy never above its start.
TEST(ContactTreatment, KrAlphaPenaltyIsTheSpringOfTheNextSampleAtAnyStep) {
  for (const double factor : {3.0, 1e4}) {
    for (const double courant : {0.5, 4.0}) {
      for (const double rho_inf : {0.0, 1.0}) {
        RodScene scene;
        scene.courant = courant;
        const double k = factor * scene.youngs_modulus * scene.area * scene.elements / scene.length;
        const std::string what = "factor " + std::to_string(factor) + ", courant " +
                                 std::to_string(courant) + ", rho_inf " + std::to_string(rho_inf);
        const testing::Run r =
            testing::run(scene, KrAlphaParams{.rho_inf = rho_inf},
                         with_contact({.law = ContactLaw::penalty, .penalty_factor = factor}));
        ASSERT_EQ(r.summary.status, RunStatus::ok) << what << ": " << r.summary.message;
        EXPECT_TRUE(r.summary.warning.empty()) << what << ": " << r.summary.warning;
        EXPECT_TRUE(std::isnan(r.summary.stable_dt)) << what;
        long active = 0;
        double largest = 0.0;
        for (long i = 0; i + 1 < r.trace.size(); ++i) {
          const double lambda = r.trace.pressure[i] * scene.area;
          const double penetration = r.trace.displacement[i + 1] - scene.gap;
          ASSERT_GE(lambda, 0.0) << what << " sample " << i;
          EXPECT_NEAR(lambda, k * std::max(0.0, penetration), 1e-9 * k * 1e-3 / factor)
              << what << " sample " << i;
          active += lambda > 0.0;
          largest = std::max(largest, penetration);
        }
        EXPECT_GT(active, 300 / courant) << what;
        EXPECT_NEAR(r.summary.max_penetration, largest, 1e-15) << what;
        EXPECT_LE(*std::max_element(r.trace.energy.begin(), r.trace.energy.end()),
                  r.summary.initial_energy * (1.0 + 1e-12))
            << what;
      }
    }
  }
}

// Uzawa's iterations reach the Lagrange multipliers: with a tight tolerance the pressures equal
// Lagrange's to 1e-6 of ρcv0, the node stays within round-off of the wall, and the iterations are
// counted; a cap below what the tolerance needs is reported.
TEST(ContactTreatment, AugmentedLagrangianConvergesToLagrange) {
  const RodScene scene;
  const double rho_c_v0 =
      scene.density * std::sqrt(scene.youngs_modulus / scene.density) * scene.velocity;
  for (const auto& [name, method] :
       std::vector<std::pair<const char*, MethodParams>>{{"hht", HhtParams{}},
                                                         {"cdm", CentralDifferenceParams{}},
                                                         {"rho-bathe", RhoBatheParams{}},
                                                         {"houbolt", HouboltParams{}}}) {
    const testing::Run lagrange = testing::run(scene, method);
    const testing::Run r = testing::run(scene, method,
                                        with_contact({.law = ContactLaw::augmented_lagrangian,
                                                      .penalty_factor = 10.0,
                                                      .augmented_tolerance = 1e-9,
                                                      .augmented_max_iterations = 1000}));
    ASSERT_EQ(r.summary.status, RunStatus::ok) << name;
    EXPECT_LT(testing::max_abs_difference(r.trace.pressure, lagrange.trace.pressure),
              1e-6 * rho_c_v0)
        << name;
    EXPECT_LT(r.summary.max_penetration, 1e-9 * scene.gap) << name;
    EXPECT_GT(r.summary.contact_iterations, 0) << name;
    EXPECT_EQ(r.summary.unconverged_contact_steps, 0) << name;
    EXPECT_TRUE(r.summary.warning.empty()) << name;

    const testing::Run capped = testing::run(
        scene, method,
        with_contact({.law = ContactLaw::augmented_lagrangian, .augmented_max_iterations = 2}));
    EXPECT_GT(capped.summary.unconverged_contact_steps, 0) << name;
    EXPECT_FALSE(capped.summary.warning.empty()) << name;
  }
}

// With the spring k = f·E·A/h at the wall the lumped rod's bound is (4 + 2f)·E/(ρh²), so central
// difference's stable Courant number is √(2/(2 + f)); a run above it is flagged before it starts.
TEST(ContactTreatment, CentralDifferencePenaltyStableStep) {
  for (double factor : {1.0, 10.0}) {
    const double courant_limit = std::sqrt(2.0 / (2.0 + factor));
    RodScene scene;
    const RodSceneDerived d = derive(scene);
    const double h_over_c = d.element_length / d.wave_speed;
    for (double courant : {0.95 * courant_limit, 1.05 * courant_limit}) {
      scene.courant = courant;
      const testing::Run r =
          testing::run(scene, CentralDifferenceParams{},
                       with_contact({.law = ContactLaw::penalty, .penalty_factor = factor}));
      EXPECT_NEAR(r.summary.stable_dt, courant_limit * h_over_c, 1e-12 * h_over_c) << factor;
      EXPECT_EQ(r.summary.warning.empty(), courant < courant_limit) << factor << " " << courant;
    }
    // Lagrange's forward increment adds no spring: the limit stays Courant 1.
    scene.courant = 0.5;
    const testing::Run lagrange = testing::run(scene, CentralDifferenceParams{});
    EXPECT_NEAR(lagrange.summary.stable_dt, h_over_c, 1e-12 * h_over_c);
  }
  // Above the limit the explicit penalty does go unstable.
  RodScene scene;
  scene.courant = 0.5;  // above √(2/12) = 0.41 for factor 10
  const testing::Run r =
      testing::run(scene, CentralDifferenceParams{},
                   with_contact({.law = ContactLaw::penalty, .penalty_factor = 10.0}));
  EXPECT_EQ(r.summary.status, RunStatus::unstable);
}

// Several bodies (a constraint between two rods) and the rod between two walls: λ >= 0 at every
// sample under every law, the penalty's penetration is bounded by its springs, the augmented
// Lagrangian's by its tolerance.
TEST(ContactTreatment, SeveralBodiesAndTwoWallsKeepNonNegativeForces) {
  Scene bodies;
  const Segment rod{.length = 20.0, .elements = 60};
  bodies.bodies.push_back(Body{.name = "striker", .velocity = 1000.0, .segments = {rod}});
  bodies.bodies.push_back(Body{.name = "target", .gap = 0.01, .segments = {rod}});
  bodies.right_wall = Wall{.gap = 0.05};
  bodies.t_end = 3e-4;
  const AssembledScene chain = assemble(bodies);
  RodScene walls;
  walls.far_gap = 0.005;
  walls.t_end = 1e-3;
  const AssembledScene rod_between = assemble(walls);
  for (ContactLaw law :
       {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    for (const auto& [name, method] :
         std::vector<std::pair<const char*, MethodParams>>{{"hht", HhtParams{}},
                                                           {"cdm", CentralDifferenceParams{}},
                                                           {"kr-alpha", KrAlphaParams{}}}) {
      for (const AssembledScene* scene : {&chain, &rod_between}) {
        SimulationWorkspace ws;
        RunOptions options;
        options.contact = {.law = law,
                           .penalty_factor = 100.0,
                           .augmented_tolerance = 1e-8,
                           .augmented_max_iterations = 500};
        const RunSummary summary = simulate(*scene, method, options, ws);
        const std::string what =
            std::string(to_string(law)) + " " + name + (scene == &chain ? " chain" : " two walls");
        if (law == ContactLaw::penalty && std::string(name) == "cdm") {
          // k = 100·K_cc: Courant 0.5 is above the explicit penalty's limit, flagged.
          EXPECT_FALSE(summary.warning.empty()) << what;
          continue;
        }
        ASSERT_EQ(summary.status, RunStatus::ok) << what << ": " << summary.message;
        for (const auto& column : ws.trace.contact_pressure) {
          for (double p : column) ASSERT_GE(p, 0.0) << what;
        }
        for (double p : ws.trace.far_pressure) ASSERT_GE(p, 0.0) << what;
        if (law == ContactLaw::lagrange) {
          EXPECT_LE(summary.max_penetration, 1e-12) << what;
        }
        if (law == ContactLaw::penalty) {
          EXPECT_GT(summary.max_penetration, 0.0) << what;
        }
        if (law == ContactLaw::augmented_lagrangian) {
          EXPECT_LT(summary.max_penetration, 1e-7) << what;
          EXPECT_GT(summary.contact_iterations, 0) << what;
        }
      }
    }
  }
}

TEST(ContactTreatment, BadSettingsAreRefusedByName) {
  EXPECT_FALSE(validate(ContactTreatment{}));
  EXPECT_EQ(validate(ContactTreatment{.penalty_stiffness = 0.0})->field, "penalty_stiffness");
  EXPECT_EQ(validate(ContactTreatment{.penalty_factor = -1.0})->field, "penalty_factor");
  EXPECT_EQ(validate(ContactTreatment{.penalty_factor = NAN})->field, "penalty_factor");
  EXPECT_EQ(validate(ContactTreatment{.augmented_tolerance = 1.0})->field, "augmented_tolerance");
  EXPECT_EQ(validate(ContactTreatment{.augmented_max_iterations = 0})->field,
            "augmented_max_iterations");
  for (ContactLaw law :
       {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    EXPECT_EQ(contact_law_from_string(to_string(law)), law);
  }
  EXPECT_FALSE(contact_law_from_string("Penalty"));
  // A run given a bad treatment fails with the field's name rather than running.
  SimulationWorkspace ws;
  RunOptions options;
  options.contact.penalty_factor = 0.0;
  const RunSummary summary = simulate(RodScene{}, HhtParams{}, options, ws);
  EXPECT_EQ(summary.status, RunStatus::failed);
  EXPECT_NE(summary.message.find("penalty_factor"), std::string::npos);
}

}  // namespace
}  // namespace impactid
