// The modified masses (core/model/rod_scene.hpp: MassMatrix::redistributed and singular): their
// matrices against the entries written out by hand, the rule for a massless DOF's initial
// acceleration, which methods step them and which are refused by name, and what they are for,
// measured on the paper's rod against its exact d'Alembert solution: far fewer spurious peaks of
// the contact pressure than the lumped mass at the same step, the Signorini conditions at every
// sample, and the energy lost by the redistributed mass shrinking with h.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/second_order_system.hpp"
#include "core/run/simulation.hpp"
#include "core/spectral/amplification.hpp"
#include "metrics/indicators.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::run;
using testing::stepping_options;

RodScene small_rod(MassMatrix mass, int elements = 8) {
  RodScene scene;
  scene.elements = elements;
  scene.mass = mass;
  return scene;
}

double element_mass(const RodScene& scene) {
  return scene.density * scene.area * scene.length / scene.elements;
}

// 1ᵀ·M·1, the mass a rigid translation sees.
double total_mass(const Tridiagonal& m) {
  return m.dense().sum();
}

TEST(MassTreatment, NamesRoundTrip) {
  for (const MassMatrix m : kMassMatrices) {
    EXPECT_EQ(mass_matrix_from_string(to_string(m)), m) << to_string(m);
    EXPECT_GT(std::string(mass_matrix_description(m)).size(), 10u);
  }
  EXPECT_STREQ(mass_matrix_names(), "lumped|consistent|redistributed|singular");
  EXPECT_FALSE(has_massless_dofs(MassMatrix::lumped));
  EXPECT_FALSE(has_massless_dofs(MassMatrix::consistent));
  EXPECT_TRUE(has_massless_dofs(MassMatrix::redistributed));
  EXPECT_TRUE(has_massless_dofs(MassMatrix::singular));
}

// Redistributed: the lumped matrix with the wall node's ρAh/2 on its neighbour, 3ρAh/2 there;
// the total mass kept. With a far wall node 0's goes to node 1 too.
TEST(MassTreatment, RedistributedMovesTheContactNodesMassToItsNeighbour) {
  for (const bool far_wall : {false, true}) {
    RodScene scene = small_rod(MassMatrix::redistributed);
    RodScene lumped = small_rod(MassMatrix::lumped);
    if (far_wall) scene.far_gap = lumped.far_gap = 0.01;
    const SecondOrderSystem s = assemble_rod(scene), l = assemble_rod(lumped);
    const double m = element_mass(scene);
    const Eigen::Index n = s.size();
    EXPECT_TRUE(s.mass.is_diagonal());
    EXPECT_EQ(s.mass.diag[n - 1], 0.0);
    EXPECT_TRUE(massless(s.mass, n - 1));
    EXPECT_DOUBLE_EQ(s.mass.diag[n - 2], 1.5 * m);
    EXPECT_EQ(massless(s.mass, 0), far_wall);
    EXPECT_DOUBLE_EQ(s.mass.diag[0], far_wall ? 0.0 : 0.5 * m);
    EXPECT_DOUBLE_EQ(s.mass.diag[1], far_wall ? 1.5 * m : m);
    for (Eigen::Index i = 2; i < n - 2; ++i) EXPECT_EQ(s.mass.diag[i], l.mass.diag[i]) << i;
    EXPECT_NEAR(total_mass(s.mass), total_mass(l.mass), 1e-14 * total_mass(l.mass));
    EXPECT_NEAR(total_mass(s.mass), scene.density * scene.area * scene.length,
                1e-14 * total_mass(l.mass));
    EXPECT_EQ(s.stiffness.diag, l.stiffness.diag);
  }
}

// Singular: the consistent matrix, the wall node's row and column zero, its neighbour's diagonal
// 7ρAh/12 (GetFEM's demo_dynamic_contact_1D, mass_matrix_type = 2); 3ρAh/4 lost per wall.
TEST(MassTreatment, SingularIsTheConsistentMassWithoutTheContactNode) {
  for (const bool far_wall : {false, true}) {
    RodScene scene = small_rod(MassMatrix::singular);
    RodScene consistent = small_rod(MassMatrix::consistent);
    if (far_wall) scene.far_gap = consistent.far_gap = 0.01;
    const SecondOrderSystem s = assemble_rod(scene), c = assemble_rod(consistent);
    const double m = element_mass(scene);
    const Eigen::Index n = s.size();
    const Eigen::MatrixXd dense = s.mass.dense(), expected_base = c.mass.dense();
    Eigen::MatrixXd expected = expected_base;
    expected.row(n - 1).setZero();
    expected.col(n - 1).setZero();
    expected(n - 2, n - 2) = 7.0 * m / 12.0;
    if (far_wall) {
      expected.row(0).setZero();
      expected.col(0).setZero();
      expected(1, 1) = 7.0 * m / 12.0;
    }
    EXPECT_LE((dense - expected).cwiseAbs().maxCoeff(), 1e-15 * m) << dense;
    EXPECT_TRUE(massless(s.mass, n - 1));
    EXPECT_EQ(massless(s.mass, 0), far_wall);
    EXPECT_FALSE(massless(s.mass, n - 2));
    const double lost = (far_wall ? 2.0 : 1.0) * 0.75 * m;
    EXPECT_NEAR(total_mass(s.mass), total_mass(c.mass) - lost, 1e-14 * total_mass(c.mass));
  }
}

// With a far wall and one element both nodes would be massless: refused by name.
TEST(MassTreatment, OneElementBetweenTwoWallsIsRefused) {
  RodScene scene = small_rod(MassMatrix::redistributed, 1);
  EXPECT_FALSE(validate(scene).has_value());
  scene.far_gap = 0.01;
  const auto error = validate(scene);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->field, "mass");
  EXPECT_EQ(error->value, "redistributed");
}

// The rule for a massless DOF's initial acceleration: the massive DOFs from M·a = −K·u − C·v, the
// massless one from its static equation differentiated twice, K_c·a = 0.
TEST(MassTreatment, InitialAccelerationOfAMasslessDofComesFromItsStaticEquation) {
  for (const MassMatrix mass : {MassMatrix::redistributed, MassMatrix::singular}) {
    const RodScene scene = small_rod(mass);
    const SecondOrderSystem system = assemble_rod(scene);
    const Eigen::Index n = system.size();
    State state;
    state.u = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3).array().square();  // strained
    state.v = Eigen::VectorXd::Constant(n, 1000.0);
    state.lambda = 0.0;
    const Eigen::VectorXd a = consistent_acceleration(system, state);
    ASSERT_TRUE(a.allFinite());
    const Eigen::MatrixXd m = system.mass.dense(), k = system.stiffness.dense();
    const Eigen::VectorXd residual = m * a + k * state.u;
    const double scale = (k * state.u).cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
      EXPECT_LE(std::abs(residual[i]), 1e-12 * scale) << to_string(mass) << " dof " << i;
    }
    EXPECT_LE(std::abs(k.row(n - 1).dot(a)), 1e-12 * k.row(n - 1).cwiseAbs().dot(a.cwiseAbs()))
        << to_string(mass);
    EXPECT_NE(a[n - 1], 0.0);  // the strained neighbour accelerates, and the node with it
    // The rod's own start, unstrained in free flight: zero everywhere.
    state.u.setZero();
    EXPECT_TRUE(consistent_acceleration(system, state).isZero(0.0));
  }
}

// Which methods step a massless DOF is each method's descriptor's to say; the others are refused
// by name, and simulate() refuses them too (a failed run, before any step).
TEST(MassTreatment, MethodsThatDoNotStepAMasslessDofAreRefusedByName) {
  int takers = 0;
  for (const MethodDescriptor& m : method_registry()) {
    const auto refusal = massless_refusal(m, 0.0);
    RodScene scene = small_rod(MassMatrix::redistributed, 50);
    const RunSummary summary = run(scene, m.defaults()).summary;
    if (m.massless_dofs) {
      ++takers;
      EXPECT_FALSE(refusal.has_value()) << m.name;
      EXPECT_EQ(summary.status, RunStatus::ok) << m.name << ": " << summary.message;
    } else {
      ASSERT_TRUE(refusal.has_value()) << m.name;
      EXPECT_NE(refusal->find(std::string("method ") + m.name + " "), std::string::npos)
          << *refusal;
      EXPECT_NE(refusal->find("cdm"), std::string::npos) << *refusal;
      EXPECT_EQ(summary.status, RunStatus::failed) << m.name;
      EXPECT_EQ(summary.message.rfind("mass = redistributed: method " + std::string(m.name), 0), 0u)
          << summary.message;
      EXPECT_EQ(summary.steps, 0) << m.name;
    }
  }
  // Central difference, the single-step implicit family, the composite schemes and Houbolt.
  EXPECT_GE(takers, 9);
  const MethodDescriptor& cdm = descriptor(MethodKind::central_difference);
  const auto damped = massless_refusal(cdm, 1e-9);
  ASSERT_TRUE(damped.has_value());
  EXPECT_NE(damped->find("rayleigh_stiffness = 1e-09"), std::string::npos) << *damped;
  EXPECT_FALSE(massless_refusal(descriptor(MethodKind::hht), 1e-9).has_value());
}

// The batched kernels assume a regular mass: those runs go through simulate().
TEST(MassTreatment, ModifiedMassesAreNotBatched) {
  for (const MassMatrix mass : kMassMatrices) {
    const RodScene scene = small_rod(mass, 50);
    RunOptions options;
    for (const MethodParams method :
         {MethodParams{HhtParams{}}, MethodParams{CentralDifferenceParams{}}}) {
      EXPECT_EQ(batchable(scene, method, options), !has_massless_dofs(mass)) << to_string(mass);
    }
  }
}

TEST(MassTreatment, SpectralBoundIsTheBasesOne) {
  EXPECT_EQ(rod_max_omega_dt(MassMatrix::redistributed, 0.5),
            rod_max_omega_dt(MassMatrix::lumped, 0.5));
  EXPECT_EQ(rod_max_omega_dt(MassMatrix::singular, 0.5),
            rod_max_omega_dt(MassMatrix::consistent, 0.5));
}

struct Measured {
  Indicators indicators;
  RunSummary summary;
  double max_violation = -1.0;       // max u_c − gap over the samples [mm]
  double min_pressure = 0.0;         // min λ/A [MPa]
  double max_gap_while_pushing = 0;  // max |u_c − gap| where λ > 0 [mm]
};

Measured measure(const RodScene& scene, const MethodParams& method,
                 double peak_prominence = IndicatorOptions{}.peak_prominence) {
  // The lumped trapezoidal rule's chatter grows the energy past the default bound.
  const testing::Run r = run(scene, method, stepping_options(100.0));
  Measured out;
  out.summary = r.summary;
  out.indicators = evaluate_indicators(scene, r.trace, r.summary,
                                       IndicatorOptions{.peak_prominence = peak_prominence});
  for (long i = 0; i < r.trace.size(); ++i) {
    const double g = r.trace.displacement[static_cast<std::size_t>(i)] - scene.gap;
    const double p = r.trace.pressure[static_cast<std::size_t>(i)];
    out.max_violation = std::max(out.max_violation, g);
    out.min_pressure = std::min(out.min_pressure, p);
    if (p > 0.0) out.max_gap_while_pushing = std::max(out.max_gap_while_pushing, std::abs(g));
  }
  return out;
}

// The point of a modified mass: with the contact node massless, its equation is static within each
// step and the contact pressure loses the chatter its inertia drives. On the paper's rod at its
// default step, for every implicit method here, the redistributed mass leaves the pressure 3
// peaks of prominence 1e-3·ρcv0 (the overshoot at the impact and its settling) where the lumped
// mass gives 8 to 81; the trapezoidal rule (Newmark δ = 0, no numerical dissipation), whose lumped
// run chatters with ε_p = 1.78 and its energy grown twelvefold, keeps ε_p below 0.01 and its
// energy. The Signorini conditions hold at every sample.
TEST(MassTreatment, ModifiedMassRemovesTheChatterOfImplicitMethods) {
  constexpr double kProminence = 1e-3;
  struct Case {
    const char* name;
    MethodParams method;
  };
  const Case cases[] = {{"trapezoidal", NewmarkParams{.delta = 0.0}},
                        {"newmark", NewmarkParams{.delta = 0.3}},
                        {"hht", HhtParams{}},
                        {"generalized-alpha", GeneralizedAlphaParams{}},
                        {"bathe", BatheParams{}},
                        {"tr-bdf2", TrBdf2Params{}}};
  for (const Case& c : cases) {
    RodScene scene;  // the paper's
    const Measured lumped = measure(scene, c.method, kProminence);
    ASSERT_EQ(lumped.summary.status, RunStatus::ok) << c.name << ": " << lumped.summary.message;
    scene.mass = MassMatrix::redistributed;
    const Measured m = measure(scene, c.method, kProminence);
    ASSERT_EQ(m.summary.status, RunStatus::ok) << c.name << ": " << m.summary.message;
    std::cout << c.name << ": NoP_p lumped " << lumped.indicators.nop_p << ", redistributed "
              << m.indicators.nop_p << "; eps_p " << lumped.indicators.eps_p << " -> "
              << m.indicators.eps_p << "\n";
    EXPECT_LE(m.indicators.nop_p, 3.0) << c.name;
    EXPECT_GE(lumped.indicators.nop_p, 2.0 * m.indicators.nop_p) << c.name;
    EXPECT_LT(m.indicators.eps_p, 0.02) << c.name;
    EXPECT_LE(m.max_violation, 1e-12) << c.name;
    EXPECT_GE(m.min_pressure, 0.0) << c.name;
    EXPECT_LE(m.max_gap_while_pushing, 1e-12) << c.name;
    EXPECT_EQ(m.indicators.contact_episodes, 1.0) << c.name;
  }
  // The trapezoidal rule: from chatter to an accurate pressure with its energy kept.
  RodScene scene;
  const Measured lumped = measure(scene, NewmarkParams{.delta = 0.0});
  EXPECT_GT(lumped.indicators.eps_p, 1.0);
  EXPECT_GT(lumped.indicators.energy_ratio, 5.0);
  for (const MassMatrix mass : {MassMatrix::redistributed, MassMatrix::singular}) {
    scene.mass = mass;
    const Measured m = measure(scene, NewmarkParams{.delta = 0.0});
    EXPECT_LT(m.indicators.eps_p, 0.03) << to_string(mass);
    EXPECT_LT(m.indicators.eps_v, 0.1) << to_string(mass);
    EXPECT_NEAR(m.indicators.energy_ratio, 1.0, 1e-3) << to_string(mass);
    EXPECT_LE(m.max_violation, 1e-12) << to_string(mass);
    EXPECT_GE(m.min_pressure, 0.0) << to_string(mass);
    EXPECT_LE(m.max_gap_while_pushing, 1e-12) << to_string(mass);
  }
}

// Houbolt, which hardly chatters with the lumped mass (5 peaks of 1e-3·ρcv0), keeps the Signorini
// conditions and its accuracy with the modified masses.
TEST(MassTreatment, HouboltStepsAMasslessDof) {
  for (const MassMatrix mass : {MassMatrix::redistributed, MassMatrix::singular}) {
    RodScene scene;
    scene.mass = mass;
    const Measured m = measure(scene, HouboltParams{}, 1e-3);
    ASSERT_EQ(m.summary.status, RunStatus::ok) << m.summary.message;
    EXPECT_LE(m.indicators.nop_p, 3.0) << to_string(mass);
    EXPECT_LT(m.indicators.eps_p, 0.02) << to_string(mass);
    EXPECT_LE(m.max_violation, 1e-12) << to_string(mass);
    EXPECT_GE(m.min_pressure, 0.0) << to_string(mass);
    EXPECT_LE(m.max_gap_while_pushing, 1e-12) << to_string(mass);
    EXPECT_EQ(m.indicators.contact_episodes, 1.0) << to_string(mass);
  }
}

// The massless node's velocity is reported by differences (core/methods/implicit_integrator.hpp):
// on the wall it is zero, where the trapezoidal rule's own velocity would alternate ±v.
TEST(MassTreatment, MasslessNodeRestsOnTheWall) {
  RodScene scene;
  scene.mass = MassMatrix::redistributed;
  const testing::Run r = run(scene, NewmarkParams{.delta = 0.0});
  ASSERT_EQ(r.summary.status, RunStatus::ok);
  long resting = 0;
  for (long i = 1; i < r.trace.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (r.trace.pressure[k] > 0.0 && r.trace.pressure[k - 1] > 0.0) {
      EXPECT_EQ(r.trace.velocity[k], 0.0) << i;
      ++resting;
    }
  }
  EXPECT_GT(resting, 700);
}

// Central difference steps the massless contact DOF from its static equation within the step:
// stable at the lumped mass's Courant numbers, on the wall exactly while it pushes, the pressure
// close to ρ·c·v0 without Carpenter's chatter, one contact episode.
TEST(MassTreatment, CentralDifferenceSolvesTheMasslessDofStatically) {
  for (const double courant : {0.5, 0.9}) {
    RodScene scene;
    scene.courant = courant;
    scene.mass = MassMatrix::redistributed;
    const Measured m = measure(scene, CentralDifferenceParams{});
    ASSERT_EQ(m.summary.status, RunStatus::ok) << m.summary.message;
    std::cout << "cdm courant " << courant << ": NoP_p " << m.indicators.nop_p << ", eps_p "
              << m.indicators.eps_p << ", eps_v " << m.indicators.eps_v << ", stable dt "
              << m.summary.stable_dt << "\n";
    EXPECT_GT(m.summary.stable_dt, derive(scene).time_step);
    EXPECT_LE(m.max_violation, 1e-12);
    EXPECT_GE(m.min_pressure, 0.0);
    EXPECT_LE(m.max_gap_while_pushing, 1e-12);
    EXPECT_EQ(m.indicators.contact_episodes, 1.0);
    EXPECT_LT(m.indicators.eps_p, 0.1);
  }
}

// With a far wall both ends are massless, and the rod bounces between them: the Signorini
// conditions hold at both walls for central difference and HHT alike.
TEST(MassTreatment, TwoWallsBothMassless) {
  for (const MethodParams method :
       {MethodParams{CentralDifferenceParams{}}, MethodParams{HhtParams{}}}) {
    RodScene scene;
    scene.elements = 50;
    scene.far_gap = 0.01;
    scene.mass = MassMatrix::redistributed;
    scene.t_end = 1e-3;
    SimulationWorkspace ws;
    const RunSummary summary = simulate(scene, method, stepping_options(), ws);
    ASSERT_EQ(summary.status, RunStatus::ok) << summary.message;
    EXPECT_LE(summary.max_penetration, 1e-12);
    const ContactTrace& t = ws.trace;
    double far_pushes = 0.0;
    for (long i = 0; i < t.size(); ++i) {
      EXPECT_GE(t.pressure[static_cast<std::size_t>(i)], 0.0);
      EXPECT_GE(t.far_pressure[static_cast<std::size_t>(i)], 0.0);
      far_pushes = std::max(far_pushes, t.far_pressure[static_cast<std::size_t>(i)]);
    }
    EXPECT_GT(far_pushes, 0.0) << "the rod reached the far wall";
  }
}

// The energy the redistributed mass loses over the impact with the trapezoidal rule (which
// conserves it without contact) shrinks as the mesh is refined at a fixed Courant number, at every
// halving of h, and at about first order in h: the least-squares slope of log(loss) over log(h)
// on n = 25..400. (Each halving alone scatters, 0.7 to 1.8, with where the impact falls between
// two steps.)
TEST(MassTreatment, RedistributedEnergyLossShrinksWithH) {
  std::vector<double> losses, log_h, log_loss;
  for (const int elements : {25, 50, 100, 200, 400}) {
    RodScene scene;
    scene.elements = elements;
    scene.mass = MassMatrix::redistributed;
    const Measured m = measure(scene, NewmarkParams{.delta = 0.0});
    ASSERT_EQ(m.summary.status, RunStatus::ok) << m.summary.message;
    losses.push_back(1.0 - m.indicators.energy_ratio);
    log_h.push_back(std::log(scene.length / elements));
    log_loss.push_back(std::log(losses.back()));
    std::cout << "n = " << elements << ": energy loss " << losses.back() << "\n";
  }
  for (std::size_t k = 0; k < losses.size(); ++k) {
    EXPECT_GT(losses[k], 0.0) << k;
    if (k > 0) {
      EXPECT_LT(losses[k], losses[k - 1]) << k;
    }
  }
  const auto count = static_cast<double>(log_h.size());
  double mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < log_h.size(); ++k) {
    mx += log_h[k] / count;
    my += log_loss[k] / count;
  }
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t k = 0; k < log_h.size(); ++k) {
    sxy += (log_h[k] - mx) * (log_loss[k] - my);
    sxx += (log_h[k] - mx) * (log_h[k] - mx);
  }
  const double order = sxy / sxx;
  std::cout << "order " << order << "\n";
  EXPECT_GT(order, 0.9);
  EXPECT_LT(order, 1.4);
}

}  // namespace
}  // namespace impactid

namespace impactid {
namespace {

// The bouncing bar of Doyen, Ern & Piperno (tests/bouncing_bar_scene_test.cpp) on 100 elements at
// Courant 1, one period and a half, with the mass given.
Scene bouncing_bar(MassMatrix mass) {
  Scene s;
  s.bodies.push_back(
      Body{.name = "bar",
           .segments = {
               Segment{.length = 10.0, .elements = 100, .youngs_modulus = 900.0, .density = 1.0}}});
  s.left_wall = Wall{.gap = 5.0};
  s.gravity = -10.0;
  s.mass = mass;
  s.courant = 1.0;
  s.t_end = 8.0;
  return s;
}

// A scene of bodies takes the modified masses at every contact node (a wall's end node, both end
// nodes of a pair), as the rod does at its wall: a scene in the paper's form assembles the rod's
// matrix entry for entry, and runs the rod's run bit for bit.
TEST(MassTreatment, AScenesContactNodesTakeTheModifiedMassAsTheRodsWall) {
  for (MassMatrix mass : {MassMatrix::redistributed, MassMatrix::singular}) {
    const RodScene rod = small_rod(mass, 20);
    const Scene scene = to_scene(rod);
    ASSERT_TRUE(in_paper_form(scene));
    ASSERT_FALSE(validate(scene).has_value());
    const AssembledScene a = assemble(scene);
    const SecondOrderSystem b = assemble_rod(rod);
    EXPECT_EQ(a.system.mass.diag, b.mass.diag) << to_string(mass);
    EXPECT_EQ(a.system.mass.lower, b.mass.lower) << to_string(mass);
    EXPECT_EQ(a.system.mass.upper, b.mass.upper) << to_string(mass);
    EXPECT_EQ(a.mass, mass);
    SimulationWorkspace wa, wb;
    const RunSummary ra = simulate(a, HhtParams{.alpha = -0.3}, RunOptions{}, wa);
    const RunSummary rb = simulate(rod, HhtParams{.alpha = -0.3}, RunOptions{}, wb);
    ASSERT_EQ(ra.status, RunStatus::ok) << ra.message;
    EXPECT_EQ(wa.trace.pressure, wb.trace.pressure) << to_string(mass);
    EXPECT_EQ(wa.trace.velocity, wb.trace.velocity) << to_string(mass);
  }
  // Two bodies between two walls: all four contact nodes lose their mass, the redistributed total
  // is the lumped one.
  Scene pair;
  pair.bodies = {Body{.name = "a", .velocity = 1000.0, .segments = {Segment{.elements = 10}}},
                 Body{.name = "b", .gap = 0.01, .segments = {Segment{.elements = 10}}}};
  pair.left_wall = Wall{.gap = 0.01};
  pair.right_wall = Wall{.gap = 0.01};
  pair.mass = MassMatrix::redistributed;
  ASSERT_FALSE(validate(pair).has_value());
  const Tridiagonal m = assemble(pair).system.mass;
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    EXPECT_EQ(massless(m, i), i == 0 || i == 10 || i == 11 || i == 21) << i;
  }
  pair.mass = MassMatrix::lumped;
  EXPECT_NEAR(m.diag.sum(), assemble(pair).system.mass.diag.sum(), 1e-22);
}

// On the bouncing bar the trapezoidal rule, whose lumped run chatters into the energy bound, runs
// with the redistributed mass and keeps its energy; the implicit steppers report the massless
// node's velocity by differences (as on the rod), and central difference, which solves a massless
// node statically only at the rod's named walls, refuses the scene's by name.
TEST(MassTreatment, TheBouncingBarsTrapezoidalRuleKeepsItsEnergyWithTheRedistributedMass) {
  SimulationWorkspace ws;
  const RunSummary lumped = simulate(assemble(bouncing_bar(MassMatrix::lumped)),
                                     NewmarkParams{.delta = 0.0}, RunOptions{}, ws);
  EXPECT_EQ(lumped.status, RunStatus::unstable) << lumped.message;
  const RunSummary redistributed = simulate(assemble(bouncing_bar(MassMatrix::redistributed)),
                                            NewmarkParams{.delta = 0.0}, RunOptions{}, ws);
  ASSERT_EQ(redistributed.status, RunStatus::ok) << redistributed.message;
  EXPECT_NEAR(redistributed.final_energy / redistributed.initial_energy, 1.0, 2e-3);
  // Held on the ground (pressed at this sample and the one before), the node's reported velocity
  // is the difference of its two positions on the wall: 0, not the trapezoidal rule's ±v.
  int held = 0;
  for (std::size_t i = 1; i < ws.trace.pressure.size(); ++i) {
    if (!(ws.trace.pressure[i] > 0.0 && ws.trace.pressure[i - 1] > 0.0)) continue;
    ++held;
    EXPECT_EQ(ws.trace.velocity[i], 0.0) << i;
  }
  EXPECT_GT(held, 100);
  const RunSummary cdm = simulate(assemble(bouncing_bar(MassMatrix::redistributed)),
                                  CentralDifferenceParams{}, RunOptions{}, ws);
  EXPECT_EQ(cdm.status, RunStatus::failed);
  EXPECT_NE(cdm.message.find("a massless contact node of a scene of bodies is not supported"),
            std::string::npos)
      << cdm.message;
}

}  // namespace
}  // namespace impactid
