// Doyen, Ern & Piperno's bouncing bar (issue 36) as a scene of bodies under gravity: a bar of
// L = 10, E = 900, ρ = 1 dropped from rest, gravity g = 10 toward the left wall, d = 5 below it
// (the fall of 3L/c). Its load is its weight with the potential above the wall
// (core/model/constant_load.hpp); its runs are measured against BouncingBarExact
// (core/reference/bouncing_bar_exact.hpp) through scene_reference(); every method of the registry
// falls at g before the impact (the load reaches every stepper); the energy, kinetic + strain +
// potential, starts at the exact ρgL·(d + L/2); the contact and its impulse converge to the exact
// ones under refinement; and what assumes bodies that fly as u = v0·t refuses the scene.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "bar_run.hpp"
#include "core/batch/batched_chain.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/sparse_system.hpp"
#include "core/reference/bouncing_bar_exact.hpp"
#include "core/run/references.hpp"
#include "core/run/simulation.hpp"
#include "metrics/indicators.hpp"

namespace impactid {
namespace {

// The benchmark on n elements at the Courant number given, up to t_end (two periods, 32/3, by
// default).
Scene bouncing_bar(int n, double courant = 0.5, double t_end = 32.0 / 3.0) {
  Scene s;
  s.bodies.push_back(
      Body{.name = "bar",
           .segments = {
               Segment{.length = 10.0, .elements = n, .youngs_modulus = 900.0, .density = 1.0}}});
  s.left_wall = Wall{.gap = 5.0};
  s.gravity = -10.0;
  s.courant = courant;
  s.t_end = t_end;
  return s;
}

using testing::BarRun;
using testing::run_bar;

// The first contact of a pressure history sampled every dt: its first and last sample's times
// with p > 0, and its impulse Σ p·Δt over that run of samples.
struct FirstContact {
  double start = NAN, end = NAN, impulse = 0.0;
};
FirstContact first_contact(const std::vector<double>& pressure, double dt) {
  FirstContact c;
  std::size_t i = 0;
  while (i < pressure.size() && !(pressure[i] > 0.0)) ++i;
  if (i == pressure.size()) return c;
  c.start = static_cast<double>(i + 1) * dt;
  // A contact run ends at the first gap of more than a few samples (the chattering of the
  // semi-discrete Lagrange contact opens it for a step or two).
  std::size_t last = i;
  for (std::size_t j = i; j < pressure.size() && j <= last + 5; ++j) {
    if (pressure[j] > 0.0) {
      last = j;
    }
  }
  for (std::size_t j = i; j <= last; ++j) c.impulse += pressure[j] * dt;
  c.end = static_cast<double>(last + 1) * dt;
  return c;
}

TEST(BouncingBarScene, TheLoadIsTheBarsWeightAndItsPotentialTheExactEnergy) {
  for (MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
    Scene scene = bouncing_bar(40);
    scene.mass = mass;
    const AssembledScene a = assemble(scene);
    const ConstantLoad& load = a.system.load;
    ASSERT_TRUE(load.active());
    ASSERT_EQ(load.force.size(), 41);
    // ρ·A·h·g = 1 · 1 · 0.25 · 10 at every inner node, half of it at the ends, toward −x.
    EXPECT_DOUBLE_EQ(load.force[0], -1.25);
    EXPECT_DOUBLE_EQ(load.force[20], -2.5);
    EXPECT_DOUBLE_EQ(load.force[40], -1.25);
    EXPECT_NEAR(load.force.sum(), -100.0, 1e-12);  // the bar's weight ρ·A·L·g
    // Σ |f_i|·(d + x_i) is the trapezoidal rule of a linear function: exact, ρgA·(d·L + L²/2).
    const BouncingBarExact exact;
    EXPECT_NEAR(load.rest_potential, exact.energy_constant(), 1e-10);
    EXPECT_NEAR(a.system.energy(Eigen::VectorXd::Zero(41), Eigen::VectorXd::Zero(41)), 1000.0,
                1e-10);
    // Moving the bar 1 down (toward the wall) lowers the potential by its weight.
    EXPECT_NEAR(load.potential(Eigen::VectorXd::Constant(41, -1.0)), 900.0, 1e-10);
    // The continuum's energy at t = 0 and the speed it strikes the wall at, g·t_f = 10.
    const SceneDerived d = derive(scene);
    EXPECT_NEAR(d.initial_energy, 1000.0, 1e-10);
    EXPECT_NEAR(d.velocity_scale, 10.0, 1e-12);
    EXPECT_NEAR(d.first_contact_time, 1.0, 1e-15);
    EXPECT_FALSE(a.starts_free);
    EXPECT_FALSE(a.rigid_flight);
  }
  // No gravity, no load: the system of every existing scene has none.
  Scene still = bouncing_bar(40);
  still.gravity = 0.0;
  EXPECT_FALSE(assemble(still).system.load.active());
  EXPECT_FALSE(assemble(RodScene{}).system.load.active());
}

TEST(BouncingBarScene, AClampedNodesWeightGoesToTheClamp) {
  // A bar hanging from a clamp on the right, falling toward nothing but its clamp: gravity points
  // to the clamp's wall, the zero of its potential.
  Scene hung = bouncing_bar(10);
  hung.gravity = 10.0;
  hung.right_wall = Wall{.kind = WallKind::clamped};
  ASSERT_FALSE(validate(hung).has_value()) << validate(hung)->constraint;
  const ConstantLoad& load = assemble(hung).system.load;
  ASSERT_EQ(load.force.size(), 10);  // node 10 is the clamp's
  EXPECT_NEAR(load.force.sum(), 100.0 - 5.0, 1e-12);
  // Heights above the clamp: 10 − x_i for the free nodes x_i = 0, 1, ..., 9.
  EXPECT_NEAR(load.rest_potential,
              5.0 * 10.0 + 10.0 * (9.0 + 8.0 + 7.0 + 6.0 + 5.0 + 4.0 + 3.0 + 2.0 + 1.0), 1e-10);
}

TEST(BouncingBarScene, GravityMustPointTowardAWall) {
  Scene up = bouncing_bar(10);
  up.gravity = 10.0;  // toward the right, where there is no wall
  const auto error = validate(up);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->field, "gravity");
  EXPECT_EQ(error->value, "10");
  EXPECT_NE(error->constraint.find("wall.right"), std::string::npos) << error->constraint;
  Scene bad = bouncing_bar(10);
  bad.gravity = NAN;
  ASSERT_TRUE(validate(bad).has_value());
  EXPECT_EQ(validate(bad)->field, "gravity");
}

TEST(BouncingBarScene, TheReferenceIsTheBouncingBarsExactSolution) {
  const Scene scene = bouncing_bar(30);
  const std::optional<BouncingBarParams> params = bouncing_bar_params(scene);
  ASSERT_TRUE(params.has_value());
  EXPECT_EQ(params->length, 10.0);
  EXPECT_EQ(params->gravity, 10.0);
  const SceneReference r = scene_reference(scene, ReferenceOptions{});
  ASSERT_TRUE(r.usable());
  EXPECT_EQ(r.exact, SceneExact::bouncing_bar);
  EXPECT_EQ(r.refinements, 0);
  EXPECT_EQ(r.description(),
            "exact solution of the bouncing bar (core/reference/bouncing_bar_exact.hpp)");
  // From the benchmark's statement: the end falls at −g·t until t = 1, then rests on the ground
  // pressing with 300·t (ρgL·t/D, D = L/c = 1/3) until t = 5/3.
  const double dt = derive(scene).time_step;
  ASSERT_EQ(r.contacts.size(), 1u);
  const ContactSamples& s = r.contacts[0];
  for (std::size_t i = 0; i < s.pressure.size(); ++i) {
    const double t = static_cast<double>(i + 1) * dt;
    if (t < 1.0 - 1e-9) {
      EXPECT_EQ(s.pressure[i], 0.0) << t;
      EXPECT_NEAR(s.velocity[i], -10.0 * t, 1e-12) << t;
    } else if (t > 1.0 + 1e-9 && t < 5.0 / 3.0 - 1e-9) {
      EXPECT_NEAR(s.pressure[i], 300.0 * t, 1e-9) << t;
      EXPECT_EQ(s.velocity[i], 0.0) << t;
    }
  }
}

TEST(BouncingBarScene, OtherFormsAreNotTheBenchmark) {
  std::vector<Scene> others(6, bouncing_bar(10));
  others[0].left_wall->gap = 4.0;           // another drop: another solution
  others[1].bodies[0].velocity = -1.0;      // thrown
  others[2].rayleigh_mass = 1e-3;           // damping
  others[3].right_wall = Wall{.gap = 1.0};  // a ceiling
  others[4].bodies[0].segments.push_back(
      Segment{.length = 1.0, .elements = 1, .youngs_modulus = 900.0, .density = 1.0});
  others[5].gravity = 0.0;  // no gravity: the chain's
  for (std::size_t k = 0; k < others.size(); ++k) {
    ASSERT_FALSE(validate(others[k]).has_value()) << k << ": " << validate(others[k])->constraint;
    EXPECT_FALSE(bouncing_bar_params(others[k]).has_value()) << k;
  }
}

// The load reaches every stepper: before the impact the bar falls rigidly, v = −g·t at every
// node, which every method of the registry integrates to round-off (a constant acceleration from
// its exact start, a₀ = M⁻¹·f = g, and no strain: K·u = 0 for a rigid translation). Its
// displacement −g·t²/2 is exact for the methods of second order and more; backward Euler's,
// u₊ = u + Δt·v₊, lags by g·Δt·t/2 (its first order), so the bound allowed is g·Δt·t. A stepper
// that left the load out would not move the bar at all (an error of g·t²/2, 50 times the bound
// here). The energy, kinetic + potential, stays the initial 1000 up to the potential of that
// lag (the weight 100 times it) and, for the methods whose energy is their own half-step one
// (central difference, KR-α: kinetic from w = (u₊ − u)/Δt, potential at m = (u + u₊)/2), its
// constant offset −m·g²·Δt²/8 in free fall.
TEST(BouncingBarScene, EveryMethodFallsAtGBeforeTheImpact) {
  for (MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
    for (const MethodDescriptor& m : method_registry()) {
      Scene scene = bouncing_bar(20, 0.5, 0.9);
      scene.mass = mass;
      const std::string name = std::string(m.name) + " (" + to_string(mass) + ")";
      const BarRun run = run_bar(scene, m.defaults(), true);
      ASSERT_EQ(run.summary.status, RunStatus::ok) << name << ": " << run.summary.message;
      EXPECT_EQ(run.summary.skipped_steps, 0) << name;  // the flight is stepped, not filled in
      const double dt = derive(scene).time_step;
      double worst_v = 0.0, worst_u = 0.0, worst_lag = 0.0;
      for (std::size_t i = 0; i < run.trace.velocity.size(); ++i) {
        const double t = static_cast<double>(i + 1) * dt;
        EXPECT_EQ(run.trace.pressure[i], 0.0) << name << " t = " << t;
        worst_v = std::max(worst_v, std::abs(run.trace.velocity[i] + 10.0 * t));
        const double lag = std::abs(run.trace.displacement[i] + 5.0 * t * t);
        worst_u = std::max(worst_u, lag);
        worst_lag = std::max(worst_lag, lag / (10.0 * dt * t));
      }
      EXPECT_LT(worst_v, 1e-9) << name;
      EXPECT_LE(worst_lag, 1.0) << name;
      const double midpoint_offset = 10.0 * 100.0 * dt * dt / 8.0;
      EXPECT_NEAR(run.summary.final_energy, 1000.0, 1e-6 + 100.0 * worst_u + midpoint_offset)
          << name;
    }
  }
}

// The sparse steppers take the load as the tridiagonal ones: the bar as a SparseSystem of the
// same matrices and load (lumped: central difference's one-pass predictor; consistent: every other
// stepper) falls as the tridiagonal bar does before the impact. Not bit for bit in general (the
// two systems' products differ in their order), so to 1e-12 of the fall's scale.
TEST(BouncingBarScene, TheSparseSystemFallsAsTheTridiagonalOne) {
  for (MassMatrix mass : {MassMatrix::lumped, MassMatrix::consistent}) {
    Scene scene = bouncing_bar(20, 0.5, 0.9);
    scene.mass = mass;
    const AssembledScene tridiagonal = assemble(scene);
    AssembledScene sparse = tridiagonal;
    auto system = std::make_shared<SparseSystem>();
    system->mass = to_sparse(tridiagonal.system.mass);
    system->stiffness = to_sparse(tridiagonal.system.stiffness);
    system->damping = SparseMatrix(21, 21);
    system->constraints = tridiagonal.system.constraints;
    system->load = tridiagonal.system.load;
    sparse.sparse = system;
    for (const MethodDescriptor& m : method_registry()) {
      if (mass == MassMatrix::consistent && std::holds_alternative<CentralDifferenceCoefficients>(
                                                stepper_coefficients(m.defaults()))) {
        continue;  // the sparse central difference needs a diagonal M
      }
      const std::string name = std::string(m.name) + " (" + to_string(mass) + ")";
      SimulationWorkspace a, b;
      const RunOptions options{.record_history = true};
      const RunSummary ra = simulate(tridiagonal, m.defaults(), options, a);
      const RunSummary rb = simulate(sparse, m.defaults(), options, b);
      ASSERT_EQ(ra.status, RunStatus::ok) << name << ": " << ra.message;
      ASSERT_EQ(rb.status, RunStatus::ok) << name << ": " << rb.message;
      ASSERT_EQ(a.trace.velocity.size(), b.trace.velocity.size());
      for (std::size_t i = 0; i < a.trace.velocity.size(); ++i) {
        ASSERT_NEAR(b.trace.velocity[i], a.trace.velocity[i], 1e-12 * 10.0) << name << " " << i;
        ASSERT_NEAR(b.trace.displacement[i], a.trace.displacement[i], 1e-12 * 5.0) << name;
      }
      EXPECT_NEAR(rb.final_energy, ra.final_energy, 1e-9) << name;
    }
  }
}

// Central difference at Courant 1 on a lumped mass converges at first order in h to the exact
// contact history (its pressure error halves with the mesh), with each contact's impulse near the
// exact 8ρgL·L/c = 800/3 and the energy lost falling likewise; HHT's (α = −0.3, δ = −α) error
// falls too, more slowly (about h^0.6: its dissipation smears the contact's linear rise of the
// pressure; the figures are in docs/remedies.md).
TEST(BouncingBarScene, CentralDifferenceConvergesAtFirstOrderAndHhtMoreSlowly) {
  std::vector<double> cdm_error, cdm_energy_lost, hht_error;
  for (int n : {50, 100, 200}) {
    const Scene scene = bouncing_bar(n, 1.0);
    const BarRun cdm = run_bar(scene, CentralDifferenceParams{});
    const BarRun hht = run_bar(scene, HhtParams{.alpha = -0.3});
    ASSERT_EQ(cdm.summary.status, RunStatus::ok) << cdm.summary.message;
    ASSERT_EQ(hht.summary.status, RunStatus::ok) << hht.summary.message;
    cdm_error.push_back(cdm.indicators.eps_p);
    cdm_energy_lost.push_back(1.0 - cdm.summary.final_energy / cdm.summary.initial_energy);
    hht_error.push_back(hht.indicators.eps_p);
    const double dt = derive(scene).time_step;
    const FirstContact c = first_contact(cdm.trace.pressure, dt);
    EXPECT_NEAR(c.start, 1.0, 2.0 * dt) << n;
    EXPECT_NEAR(c.end, 5.0 / 3.0, 2.0 * dt) << n;
    EXPECT_NEAR(c.impulse, 800.0 / 3.0, 0.005 * 800.0 / 3.0) << n;
  }
  for (std::size_t k = 1; k < cdm_error.size(); ++k) {
    const double order = std::log2(cdm_error[k - 1] / cdm_error[k]);
    EXPECT_GT(order, 0.9) << k;
    EXPECT_LT(order, 1.1) << k;
    EXPECT_GT(cdm_energy_lost[k], 0.0) << k;
    EXPECT_LT(cdm_energy_lost[k], 0.6 * cdm_energy_lost[k - 1]) << k;
    EXPECT_LT(hht_error[k], 0.8 * hht_error[k - 1]) << k;
  }
  EXPECT_LT(cdm_error.back(), 0.015);
  EXPECT_GT(hht_error.back(), 0.05);  // the implicit method stays far above central difference
}

// Paoli–Schatzman's law (central difference with the gap held on (u_{n+1} + e·u_{n−1})/(1 + e))
// converges at first order too; at e = 0.25 its pressure error is under half Lagrange's on every
// mesh, and its energy at the end within 0.5 % of the exact one (docs/remedies.md).
TEST(BouncingBarScene, PaoliSchatzmanConvergesAtFirstOrderBelowLagrangesError) {
  const ContactTreatment paoli_schatzman{.law = ContactLaw::paoli_schatzman, .restitution = 0.25};
  std::vector<double> error;
  for (int n : {50, 100, 200}) {
    const Scene scene = bouncing_bar(n, 1.0);
    const BarRun lagrange = run_bar(scene, CentralDifferenceParams{});
    const BarRun ps = run_bar(scene, CentralDifferenceParams{}, false, paoli_schatzman);
    ASSERT_EQ(ps.summary.status, RunStatus::ok) << ps.summary.message;
    EXPECT_LT(ps.indicators.eps_p, 0.5 * lagrange.indicators.eps_p) << n;
    EXPECT_NEAR(ps.summary.final_energy / ps.summary.initial_energy, 1.0, 0.005) << n;
    error.push_back(ps.indicators.eps_p);
  }
  for (std::size_t k = 1; k < error.size(); ++k) {
    const double order = std::log2(error[k - 1] / error[k]);
    EXPECT_GT(order, 0.9) << k;
    EXPECT_LT(order, 1.3) << k;
  }
}

TEST(BouncingBarScene, TheBatchedChainKernelLeavesItToSimulate) {
  const AssembledScene a = assemble(bouncing_bar(20));
  EXPECT_FALSE(chain_batchable(a, NewmarkParams{}, RunOptions{}));
  EXPECT_FALSE(as_rod(bouncing_bar(20)).has_value());
}

}  // namespace
}  // namespace impactid
