// The d'Alembert solution of the rod impact, against values worked out from its definition.
#include "core/reference/exact_solution.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace impactid {
namespace {

struct Reference {  // computed here from the scene, not from derive()
  double c, t_impact, t_release, pressure;
};
Reference reference(const RodScene& s) {
  const double c = std::sqrt(s.youngs_modulus / s.density);
  return {c, s.gap / s.velocity, s.gap / s.velocity + 2 * s.length / c, s.density * c * s.velocity};
}

// The impact and release times fix every indicator's sample classification.
TEST(RodImpactExact, ImpactAndReleaseTimes) {
  const RodScene scene;
  const Reference r = reference(scene);
  const RodImpactExact exact(scene);
  EXPECT_DOUBLE_EQ(exact.impact_time(), 1e-5);  // 0.01 mm at 1000 mm/s
  EXPECT_DOUBLE_EQ(exact.release_time(), r.t_impact + 2 * scene.length / r.c);
  EXPECT_NEAR(exact.release_time() - exact.impact_time(), 3.7357e-4, 1e-8);  // 40 mm / c
}

// The three phases: free flight, contact at ρcv0 with the node at rest, rebound at −v0.
TEST(RodImpactExact, ValuesBeforeDuringAndAfterContact) {
  const RodScene scene;
  const Reference r = reference(scene);
  const RodImpactExact exact(scene);

  const double t_before = 0.4 * r.t_impact;
  const ContactNodeValues before = exact.at(t_before, 0.0);
  EXPECT_EQ(before.pressure, 0.0);
  EXPECT_EQ(before.velocity, scene.velocity);
  EXPECT_DOUBLE_EQ(before.displacement, scene.velocity * t_before);

  const ContactNodeValues during = exact.at(0.5 * (r.t_impact + r.t_release), 0.0);
  EXPECT_DOUBLE_EQ(during.pressure, r.pressure);
  EXPECT_NEAR(during.pressure, 0.8405, 1e-4);
  EXPECT_EQ(during.velocity, 0.0);
  EXPECT_EQ(during.displacement, scene.gap);

  const double t_after = r.t_release + 1e-5;
  const ContactNodeValues after = exact.at(t_after, 0.0);
  EXPECT_EQ(after.pressure, 0.0);
  EXPECT_EQ(after.velocity, -scene.velocity);
  EXPECT_NEAR(after.displacement, scene.gap - scene.velocity * 1e-5, 1e-15);
}

// The displacement is continuous at both jumps; only p and v jump.
TEST(RodImpactExact, DisplacementIsContinuousAcrossJumps) {
  const RodScene scene;
  const RodImpactExact exact(scene);
  for (double jump : {exact.impact_time(), exact.release_time()}) {
    const double eps = 1e-12;
    // Over 2·eps the displacement moves by at most |v0|·2·eps.
    EXPECT_NEAR(exact.at(jump - eps, 0.0).displacement, exact.at(jump + eps, 0.0).displacement,
                3 * scene.velocity * eps)
        << jump;
  }
}

// Gap 0: the first sample t = 0 sits on the impact and takes the mean of the two limits.
TEST(RodImpactExact, MeanOfLimitsOnImpactAtTimeZero) {
  RodScene scene;
  scene.gap = 0.0;
  const Reference r = reference(scene);
  const RodImpactExact exact(scene);
  const ContactNodeValues on_jump = exact.at_sample(0);
  EXPECT_DOUBLE_EQ(on_jump.pressure, 0.5 * r.pressure);
  EXPECT_DOUBLE_EQ(on_jump.velocity, 0.5 * scene.velocity);
  EXPECT_EQ(on_jump.displacement, 0.0);
  EXPECT_DOUBLE_EQ(exact.at_sample(1).pressure, r.pressure);  // next sample fully in contact
}

// gap = k·Δt·v0 puts sample k on the impact; Δt = (2L/c)/m puts sample k + m on the release.
TEST(RodImpactExact, MeanOfLimitsOnSampledJumps) {
  RodScene scene;
  const Reference r0 = reference(scene);
  const int k = 7, m = 400;
  const double dt = (2 * scene.length / r0.c) / m;
  scene.dt = dt;
  scene.gap = k * dt * scene.velocity;
  const Reference r = reference(scene);
  const RodImpactExact exact(scene);

  const ContactNodeValues impact = exact.at_sample(k);
  EXPECT_DOUBLE_EQ(impact.pressure, 0.5 * r.pressure);
  EXPECT_DOUBLE_EQ(impact.velocity, 0.5 * scene.velocity);
  EXPECT_DOUBLE_EQ(impact.displacement, scene.gap);
  EXPECT_EQ(exact.at_sample(k - 1).pressure, 0.0);
  EXPECT_DOUBLE_EQ(exact.at_sample(k + 1).pressure, r.pressure);

  const ContactNodeValues release = exact.at_sample(k + m);
  EXPECT_DOUBLE_EQ(release.pressure, 0.5 * r.pressure);
  EXPECT_DOUBLE_EQ(release.velocity, -0.5 * scene.velocity);
  EXPECT_DOUBLE_EQ(release.displacement, scene.gap);
  EXPECT_DOUBLE_EQ(exact.at_sample(k + m - 1).pressure, r.pressure);
  EXPECT_EQ(exact.at_sample(k + m + 1).pressure, 0.0);
  EXPECT_EQ(exact.at_sample(k + m + 1).velocity, -scene.velocity);
}

// Only samples within the tolerance are averaged; a sample just outside takes the one-sided value.
TEST(RodImpactExact, JumpToleranceIsRespected) {
  const RodScene scene;
  const Reference r = reference(scene);
  const RodImpactExact exact(scene);
  const double tol = 1e-12;
  EXPECT_DOUBLE_EQ(exact.at(r.t_impact + 0.5 * tol, tol).pressure, 0.5 * r.pressure);
  EXPECT_DOUBLE_EQ(exact.at(r.t_impact + 2.0 * tol, tol).pressure, r.pressure);
  EXPECT_EQ(exact.at(r.t_impact - 2.0 * tol, tol).pressure, 0.0);
}

// Moving away from the wall: free flight forever.
TEST(RodImpactExact, NoContactWhenMovingAway) {
  RodScene scene;
  scene.velocity = -1000.0;
  const RodImpactExact exact(scene);
  EXPECT_TRUE(std::isinf(exact.impact_time()));
  const ContactNodeValues v = exact.at(1e-3, 0.0);
  EXPECT_EQ(v.pressure, 0.0);
  EXPECT_EQ(v.velocity, -1000.0);
  EXPECT_DOUBLE_EQ(v.displacement, -1.0);
}

}  // namespace
}  // namespace impactid
