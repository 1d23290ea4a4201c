// The rod scene: its derived quantities, its validation and the assembled matrices.
#include "core/model/rod_scene.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "core/model/second_order_system.hpp"

namespace impactid {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Every indicator is scaled by these numbers; the values are worked by hand from the paper's data
// (E = 90 MPa, ρ = 7.85e-9 t/mm³, L = 20 mm, n = 200, v0 = 1000 mm/s, gap 0.01 mm, Courant 0.5).
TEST(RodScene, DerivedQuantitiesOfTheDefaultScene) {
  const RodScene scene;
  const RodSceneDerived d = derive(scene);
  const double c = std::sqrt(90.0 / 7.85e-9);
  EXPECT_NEAR(d.wave_speed, 107075.0, 1.0);  // √(1.1465e10) = 107 075.1 mm/s
  EXPECT_DOUBLE_EQ(d.wave_speed, c);
  EXPECT_DOUBLE_EQ(d.element_length, 0.1);
  EXPECT_DOUBLE_EQ(d.time_step, 0.5 * 0.1 / c);
  EXPECT_DOUBLE_EQ(d.impact_time, 1e-5);
  EXPECT_DOUBLE_EQ(d.contact_duration, 40.0 / c);
  EXPECT_DOUBLE_EQ(d.end_time, 1e-5 + 1.5 * 40.0 / c);
  // t_end/Δt = 1e-5·c/0.05 + 1.5·40/0.05 = 21.415 + 1200 → 1222 samples.
  EXPECT_EQ(d.step_count, 1222);
  EXPECT_NEAR(d.pressure_scale, 0.8405, 1e-4);
  EXPECT_DOUBLE_EQ(d.pressure_scale, 7.85e-9 * c * 1000.0);
  EXPECT_DOUBLE_EQ(d.initial_energy, 0.5 * 7.85e-9 * 20.0 * 1e6);
}

// An explicit dt or t_end must win over the Courant number and the default end time.
TEST(RodScene, ExplicitTimeStepAndEndTimeOverrideDefaults) {
  RodScene scene;
  scene.dt = 1e-7;
  scene.t_end = 1e-5;
  const RodSceneDerived d = derive(scene);
  EXPECT_DOUBLE_EQ(d.time_step, 1e-7);
  EXPECT_DOUBLE_EQ(d.end_time, 1e-5);
  EXPECT_EQ(d.step_count, 100);  // 1e-5/1e-7 is 100 up to round-off: no extra sample

  RodScene courant_one;
  courant_one.courant = 1.0;
  EXPECT_DOUBLE_EQ(derive(courant_one).time_step, 0.1 / std::sqrt(90.0 / 7.85e-9));
}

// A rod moving away from the wall never hits it.
TEST(RodScene, NoImpactWhenMovingAway) {
  RodScene scene;
  scene.velocity = -5.0;
  const RodSceneDerived d = derive(scene);
  EXPECT_TRUE(std::isinf(d.impact_time));
  EXPECT_GT(d.impact_time, 0.0);
  EXPECT_DOUBLE_EQ(d.pressure_scale, 7.85e-9 * d.wave_speed * 5.0);  // |v0|
  EXPECT_TRUE(std::isfinite(d.end_time));
}

// The defaults are what every plan starts from; they must pass their own validation.
TEST(RodScene, DefaultSceneIsValid) { EXPECT_FALSE(validate(RodScene{}).has_value()); }

// Validation names the offending field (habit 3: validate, never clamp).
TEST(RodScene, ValidateRejectsBadValuesNamingTheField) {
  struct Case {
    const char* field;
    void (*spoil)(RodScene&);
  };
  const Case cases[] = {
      {"elements", [](RodScene& s) { s.elements = 0; }},
      {"elements", [](RodScene& s) { s.elements = -3; }},
      {"courant", [](RodScene& s) { s.courant = 0.0; }},
      {"density", [](RodScene& s) { s.density = -7.85e-9; }},
      {"velocity", [](RodScene& s) { s.velocity = kNan; }},
      {"length", [](RodScene& s) { s.length = 0.0; }},
      {"youngs_modulus", [](RodScene& s) { s.youngs_modulus = std::numeric_limits<double>::infinity(); }},
      {"area", [](RodScene& s) { s.area = -1.0; }},
      {"gap", [](RodScene& s) { s.gap = -0.01; }},
      {"rayleigh_mass", [](RodScene& s) { s.rayleigh_mass = -1.0; }},
      {"rayleigh_stiffness", [](RodScene& s) { s.rayleigh_stiffness = kNan; }},
      {"dt", [](RodScene& s) { s.dt = 0.0; }},
      {"dt", [](RodScene& s) { s.dt = std::numeric_limits<double>::infinity(); }},
      {"t_end", [](RodScene& s) { s.t_end = kNan; }},
      {"t_end", [](RodScene& s) { s.t_end = -1.0; }},
  };
  for (const Case& c : cases) {
    RodScene scene;
    c.spoil(scene);
    const auto error = validate(scene);
    ASSERT_TRUE(error.has_value()) << c.field;
    EXPECT_EQ(error->field, c.field);
    EXPECT_FALSE(error->constraint.empty()) << c.field;
  }
  RodScene zero_elements;
  zero_elements.elements = 0;
  EXPECT_EQ(validate(zero_elements)->value, "0");
  RodScene nan_velocity;
  nan_velocity.velocity = kNan;
  EXPECT_EQ(validate(nan_velocity)->value, "nan");
}

// Gap 0 (touching the wall at t = 0) is a legal, useful scene.
TEST(RodScene, ZeroGapIsAccepted) {
  RodScene scene;
  scene.gap = 0.0;
  EXPECT_FALSE(validate(scene).has_value());
  EXPECT_EQ(derive(scene).impact_time, 0.0);
}

// Mass-matrix names go to plan files and HDF5 attributes; they must round-trip.
TEST(RodScene, MassMatrixNamesRoundTrip) {
  for (MassMatrix m : {MassMatrix::lumped, MassMatrix::consistent}) {
    EXPECT_EQ(mass_matrix_from_string(to_string(m)), m);
  }
  EXPECT_STREQ(to_string(MassMatrix::lumped), "lumped");
  EXPECT_STREQ(to_string(MassMatrix::consistent), "consistent");
  EXPECT_FALSE(mass_matrix_from_string("diagonal").has_value());
}

RodScene small_scene(MassMatrix mass) {
  RodScene scene;
  scene.elements = 7;
  scene.length = 3.5;  // h = 0.5
  scene.area = 2.0;
  scene.mass = mass;
  return scene;
}

// The total mass ρAL must be preserved by both mass matrices (rigid translation momentum).
TEST(AssembleRod, TotalMassIsRhoAL) {
  for (MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
    const RodScene scene = small_scene(mass);
    const SecondOrderSystem system = assemble_rod(scene);
    const double total = system.mass.dense().sum();  // 1ᵀ·M·1
    EXPECT_NEAR(total, scene.density * scene.area * scene.length,
                1e-14 * scene.density * scene.area * scene.length)
        << to_string(mass);
  }
}

// A free rod must admit rigid motion without elastic force: K·1 = 0 exactly.
TEST(AssembleRod, RigidTranslationIsStressFree) {
  const SecondOrderSystem system = assemble_rod(small_scene(MassMatrix::lumped));
  Eigen::VectorXd f(system.size());
  system.stiffness.multiply(Eigen::VectorXd::Constant(system.size(), 3.25), f);
  EXPECT_EQ(f.lpNorm<Eigen::Infinity>(), 0.0);
}

// Node masses of the lumped matrix: ρAh/2 at the ends, ρAh inside; the contact node is the last.
TEST(AssembleRod, LumpedMassEndsAndInterior) {
  const RodScene scene = small_scene(MassMatrix::lumped);
  const SecondOrderSystem system = assemble_rod(scene);
  const double element_mass = scene.density * scene.area * 0.5;
  ASSERT_EQ(system.size(), 8);
  EXPECT_TRUE(system.mass.is_diagonal());
  EXPECT_DOUBLE_EQ(system.mass.diag[0], element_mass / 2);
  EXPECT_DOUBLE_EQ(system.mass.diag[7], element_mass / 2);
  for (int i = 1; i < 7; ++i) EXPECT_DOUBLE_EQ(system.mass.diag[i], element_mass) << i;
  EXPECT_EQ(system.contact_dof, 7);
  EXPECT_EQ(system.gap, scene.gap);
  EXPECT_TRUE(system.has_contact());
  EXPECT_FALSE(system.has_damping());
}

// Both matrices against a dense assembly of the textbook element matrices.
TEST(AssembleRod, MatricesMatchDenseElementAssembly) {
  const RodScene scene = small_scene(MassMatrix::consistent);
  const SecondOrderSystem system = assemble_rod(scene);
  const double h = 0.5, k = scene.youngs_modulus * scene.area / h;
  const double m = scene.density * scene.area * h;
  Eigen::MatrixXd kk = Eigen::MatrixXd::Zero(8, 8), mm = Eigen::MatrixXd::Zero(8, 8);
  Eigen::Matrix2d ke, me;
  ke << k, -k, -k, k;
  me << m / 3, m / 6, m / 6, m / 3;
  for (int e = 0; e < 7; ++e) {
    kk.block<2, 2>(e, e) += ke;
    mm.block<2, 2>(e, e) += me;
  }
  EXPECT_LE((system.stiffness.dense() - kk).norm(), 1e-14 * kk.norm());
  EXPECT_LE((system.mass.dense() - mm).norm(), 1e-14 * mm.norm());
}

// Rayleigh damping C = a0·M + a1·K.
TEST(AssembleRod, RayleighDamping) {
  RodScene scene = small_scene(MassMatrix::consistent);
  scene.rayleigh_mass = 3.0;
  scene.rayleigh_stiffness = 2e-7;
  const SecondOrderSystem system = assemble_rod(scene);
  const Eigen::MatrixXd expected = 3.0 * system.mass.dense() + 2e-7 * system.stiffness.dense();
  EXPECT_TRUE(system.has_damping());
  EXPECT_LE((system.damping.dense() - expected).norm(), 1e-14 * expected.norm());
}

// The energy is ½vᵀMv + ½uᵀKu; for a rigid translation it is the kinetic energy ½ρALv0².
TEST(AssembleRod, EnergyOfRigidTranslation) {
  const RodScene scene;
  const SecondOrderSystem system = assemble_rod(scene);
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(system.size(), scene.velocity);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(system.size(), 0.004);
  const double expected = 0.5 * scene.density * scene.area * scene.length * 1e6;
  EXPECT_NEAR(system.energy(u, v), expected, 1e-13 * expected);
}

}  // namespace
}  // namespace impactid

namespace impactid {
namespace {

// derive() runs before validate() has rejected absurd inputs: a step count beyond long (here
// 1e297 steps) must not be computed by an undefined float-to-long cast (found by UBSan).
TEST(RodSceneDerive, HugeStepCountsSaturate) {
  RodScene scene;
  scene.dt = 1e-300;
  EXPECT_EQ(derive(scene).step_count, std::numeric_limits<long>::max());
  ASSERT_TRUE(validate(scene).has_value());
  EXPECT_EQ(validate(scene)->field, "dt");
}

}  // namespace
}  // namespace impactid
