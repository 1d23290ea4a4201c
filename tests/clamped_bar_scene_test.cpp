// Doyen, Ern & Piperno's clamped bar (issue 36) as a scene of bodies: a bar on [0, 1] clamped at
// x = 1 (WallKind::clamped), released from u = ½(1 − x) at rest onto an obstacle at x = 0 (the left
// wall at gap 0), E = ρ = 1. Its runs are measured against ClampedBarExact
// (core/reference/clamped_bar_exact.hpp) through scene_reference(), in the scene's signs; central
// difference at Courant 1 with a lumped mass reproduces the exact contact history at the nodes,
// an implicit method converges to it, the energy stays near 1/8; and what assumes bodies that
// start free refuses the scene (the exact solution of the chain, the batched chain kernel, the
// filled-in free flight).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bar_run.hpp"
#include "core/batch/batched_chain.hpp"
#include "core/model/scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/chain_exact.hpp"
#include "core/reference/clamped_bar_exact.hpp"
#include "core/run/references.hpp"
#include "core/run/simulation.hpp"
#include "metrics/indicators.hpp"

namespace impactid {
namespace {

// The benchmark on n elements at the Courant number given, up to t_end (two periods by default).
Scene clamped_bar(int n, double courant = 1.0, double t_end = 6.0) {
  Scene s;
  s.bodies.push_back(Body{
      .name = "bar",
      .segments = {Segment{.length = 1.0, .elements = n, .youngs_modulus = 1.0, .density = 1.0}},
      .displacement = {.left = 0.5, .right = 0.0}});
  s.left_wall = Wall{.gap = 0.0};
  s.right_wall = Wall{.kind = WallKind::clamped};
  s.courant = courant;
  s.t_end = t_end;
  return s;
}

using testing::BarRun;
using testing::run_bar;

// The largest difference of a run's samples from the reference's, over the samples whose time
// lies at least `margin` from every jump of the exact solution (t ≡ 0, 1, 2 mod 3), or over all
// of them (margin < 0).
double largest_difference(const std::vector<double>& run, const std::vector<double>& exact,
                          double dt, double margin) {
  double largest = 0.0;
  for (std::size_t i = 0; i < run.size(); ++i) {
    const double t = static_cast<double>(i + 1) * dt;
    const double to_jump = std::abs(t - std::round(t));  // the jumps are at the integers
    if (margin >= 0.0 && to_jump < margin) continue;
    largest = std::max(largest, std::abs(run[i] - exact[i]));
  }
  return largest;
}

TEST(ClampedBarScene, TheReferenceIsTheClampedBarsExactSolutionInTheScenesSigns) {
  const Scene scene = clamped_bar(10);
  const std::optional<ClampedBarParams> params = clamped_bar_params(scene);
  ASSERT_TRUE(params.has_value());
  EXPECT_EQ(params->amplitude, 0.5);
  EXPECT_EQ(params->length, 1.0);
  const SceneReference r = scene_reference(scene, ReferenceOptions{});
  ASSERT_TRUE(r.usable());
  EXPECT_EQ(r.exact, SceneExact::clamped_bar);
  EXPECT_EQ(r.refinements, 0);
  EXPECT_EQ(r.description(),
            "exact solution of the clamped bar (core/reference/clamped_bar_exact.hpp)");
  // The phases of the benchmark, from its statement: the end falls toward the obstacle at
  // ½ (−x, the scene's negative velocity) for t in (0, 1), rests on it pressing with ½ for
  // (1, 2), leaves at +½ for (2, 3); period 3.
  const double dt = derive(scene).time_step;
  ASSERT_EQ(r.contacts.size(), 1u);
  const ContactSamples& s = r.contacts[0];
  for (std::size_t i = 0; i < s.pressure.size(); ++i) {
    const double t = static_cast<double>(i + 1) * dt;
    const double phase = std::fmod(t, 3.0);
    if (std::abs(phase - std::round(phase)) < 1e-9) continue;  // on a jump: the mean
    const double p = phase > 1.0 && phase < 2.0 ? 0.5 : 0.0;
    const double v = phase < 1.0 ? -0.5 : (phase < 2.0 ? 0.0 : 0.5);
    EXPECT_EQ(s.pressure[i], p) << "t = " << t;
    EXPECT_EQ(s.velocity[i], v) << "t = " << t;
  }
  // On a jump, the mean of the two sides: at t = 1 the end lands (v from −½ to 0, p from 0 to ½).
  const auto at_one = static_cast<std::size_t>(std::lround(1.0 / dt)) - 1;
  ASSERT_NEAR(static_cast<double>(at_one + 1) * dt, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.velocity[at_one], -0.25);
  EXPECT_DOUBLE_EQ(s.pressure[at_one], 0.25);
}

TEST(ClampedBarScene, OtherFormsAreNotTheBenchmark) {
  std::vector<Scene> others(6, clamped_bar(10));
  others[0].left_wall->gap = 0.1;       // a gap to the obstacle
  others[1].bodies[0].velocity = 0.1;   // an initial velocity
  others[2].rayleigh_stiffness = 1e-3;  // damping
  others[3].bodies[0].segments.push_back(
      Segment{.length = 1.0, .elements = 10, .youngs_modulus = 1.0, .density = 1.0});
  others[4].right_wall = Wall{.gap = 0.0};      // an obstacle on the right, no clamp
  others[5].bodies[0].displacement.left = 0.0;  // at rest, unstrained: nothing moves
  for (std::size_t k = 0; k < others.size(); ++k) {
    ASSERT_FALSE(validate(others[k]).has_value()) << k << ": " << validate(others[k])->constraint;
    EXPECT_FALSE(clamped_bar_params(others[k]).has_value()) << k;
  }
  // Undamped, not the benchmark, and not starting free: neither exact solution claims it, so
  // its reference is a converged one.
  Scene moving = others[1];
  moving.t_end = 3.0;
  const SceneReference r = scene_reference(moving, ReferenceOptions{.max_refinements = 2});
  EXPECT_EQ(r.exact, SceneExact::none);
  EXPECT_GE(r.refinements, 1);
  EXPECT_NE(r.description().find("hht at h/"), std::string::npos) << r.description();
}

TEST(ClampedBarScene, TheExactSolutionOfTheChainRefusesAClampOrAnInitialStrain) {
  EXPECT_THROW(ChainExact(clamped_bar(10), 3.0), std::invalid_argument);
  Scene stretched = to_scene(RodScene{});  // the paper's rod, pre-stretched
  stretched.bodies[0].displacement = {.left = 0.0, .right = 0.001};
  ASSERT_FALSE(validate(stretched).has_value());
  EXPECT_THROW(ChainExact(stretched, 1e-4), std::invalid_argument);
  EXPECT_NO_THROW(ChainExact(to_scene(RodScene{}), 1e-4));
  // The free rod's reference is the chain's, as always.
  EXPECT_EQ(scene_reference(to_scene(RodScene{}), ReferenceOptions{}).exact, SceneExact::chain);
}

// For the 1D wave equation with a lumped mass, central difference at Courant 1 is the exact
// d'Alembert recurrence at the nodes, and the clamp (a removed DOF) and the obstacle's Lagrange
// multiplier keep it so for this piecewise-linear solution. Measured, n = 20 and 100 over two
// periods: the contact pressure and the contact node's (central) velocity equal the exact ones
// to round-off (below 1e-11 of the scale ½) at every sample but those on a jump of the exact
// solution (t = 1, 2, 3, 4, 5, 6). On a jump the exact sample is the mean of its two sides; the
// run gives the mean at the first landing (t = 1) and at the top of each rebound (t = 3, 6), and
// one side at the releases (t = 2, 5) and at the second landing (t = 4, the node there a step
// early: its displacement after a release climbs in steps of h two samples long). So ε_p is
// exactly those three samples' ¼ over Σ|p|: 0.75/n.
TEST(ClampedBarScene, CentralDifferenceAtCourantOneReproducesTheExactContactHistory) {
  for (const int n : {20, 100}) {
    const Scene scene = clamped_bar(n);
    const BarRun r = run_bar(scene, CentralDifferenceParams{});
    ASSERT_EQ(r.summary.status, RunStatus::ok) << r.summary.message;
    const double dt = derive(scene).time_step;
    ASSERT_EQ(dt, 1.0 / n);
    const ContactSamples& exact = r.reference.contacts[0];
    EXPECT_LT(largest_difference(r.trace.pressure, exact.pressure, dt, 0.5 * dt), 1e-11) << n;
    EXPECT_LT(largest_difference(r.trace.velocity, exact.velocity, dt, 0.5 * dt), 1e-11) << n;
    // On a jump: the mean or one of the two sides, ½ apart.
    for (int k = 1; k <= 6; ++k) {
      const auto i = static_cast<std::size_t>(k * n - 1);
      for (const auto& [run, mean] : {std::pair{r.trace.pressure[i], exact.pressure[i]},
                                      std::pair{r.trace.velocity[i], exact.velocity[i]}}) {
        const double off = std::abs(run - mean);
        EXPECT_TRUE(off < 1e-11 || std::abs(off - 0.25) < 1e-11) << n << " t = " << k;
      }
    }
    EXPECT_NEAR(r.indicators.eps_p, 0.75 / n, 1e-10) << n;
    EXPECT_LT(r.indicators.eps_v, 0.4 / n) << n;  // measured 0.385/n and 0.377/n
    EXPECT_NEAR(r.indicators.p_max, 0.5, 1e-11) << n;
  }
}

// An implicit method's error falls as the mesh and the step are refined together at Courant 1:
// HHT (α = −0.3, δ = 0.3), n = 25 to 400. Measured: ε_p 0.251, 0.177, 0.120, 0.078, 0.050 and ε_v
// 0.310, 0.207, 0.139, 0.089, 0.057, about h^0.6, the rate of a solution with jumps
// (tests/scene_simulation_test.cpp sees the same on two rods).
TEST(ClampedBarScene, TheImplicitErrorFallsUnderRefinement) {
  std::vector<double> eps_p, eps_v;
  for (const int n : {25, 50, 100, 200, 400}) {
    const BarRun r = run_bar(clamped_bar(n), HhtParams{.alpha = -0.3});
    ASSERT_EQ(r.summary.status, RunStatus::ok) << r.summary.message;
    eps_p.push_back(r.indicators.eps_p);
    eps_v.push_back(r.indicators.eps_v);
  }
  for (std::size_t k = 1; k < eps_p.size(); ++k) {
    EXPECT_LT(eps_p[k], 0.75 * eps_p[k - 1]) << k;
    EXPECT_LT(eps_v[k], 0.75 * eps_v[k - 1]) << k;
  }
  EXPECT_LT(eps_p.back(), 0.055);
  EXPECT_LT(eps_v.back(), 0.065);
}

// The energy starts at the benchmark's 1/8 (½uᵀKu of the interpolated linear field: exact) and
// stays near it. Central difference's own discrete energy is constant to round-off but for the
// contact node's kinetic energy ½·(ρh/2)·(½)² = h/16, lost when the multiplier stops the node on
// the obstacle at the first landing (measured: no loss at the second): within h/8 of 1/8, the
// energy ratio 1 − h. HHT (α = −0.3) dissipates, never above 1/8; measured at n = 50 its energy
// ratio after two periods is 0.934 (0.883, 0.960, 0.976, 0.986 at n = 25, 100, 200, 400).
TEST(ClampedBarScene, TheEnergyStaysNearOneEighth) {
  const int n = 50;
  const double h = 1.0 / n;
  const BarRun cdm = run_bar(clamped_bar(n), CentralDifferenceParams{}, true);
  ASSERT_EQ(cdm.summary.status, RunStatus::ok);
  EXPECT_NEAR(cdm.summary.initial_energy, 0.125, 1e-15);
  for (const double e : cdm.trace.energy) {
    EXPECT_LE(e, 0.125 + 1e-12);
    EXPECT_GE(e, 0.125 - h / 8.0 - 1e-12);
  }
  EXPECT_NEAR(cdm.indicators.energy_ratio, 1.0 - h, 1e-10);
  const BarRun hht = run_bar(clamped_bar(n), HhtParams{.alpha = -0.3}, true);
  ASSERT_EQ(hht.summary.status, RunStatus::ok);
  EXPECT_NEAR(hht.summary.initial_energy, 0.125, 1e-15);
  for (const double e : hht.trace.energy) EXPECT_LE(e, 0.125);
  EXPECT_GT(hht.indicators.energy_ratio, 0.92);
  EXPECT_LT(hht.indicators.energy_ratio, 0.95);
}

TEST(ClampedBarScene, TheBatchedChainKernelAndTheFilledInFlightRefuseIt) {
  const MethodParams hht = HhtParams{.alpha = -0.3};
  const RunOptions options;
  const AssembledScene clamped = assemble(clamped_bar(20));
  EXPECT_FALSE(clamped.starts_free);
  EXPECT_FALSE(chain_batchable(clamped, hht, options));
  // The same bar, free and unstrained, moving onto the obstacle: the kernel takes it.
  Scene free_bar = clamped_bar(20);
  free_bar.right_wall.reset();
  free_bar.bodies[0].displacement = {};
  free_bar.bodies[0].velocity = -0.5;
  free_bar.left_wall->gap = 0.5;
  const AssembledScene free = assemble(free_bar);
  EXPECT_TRUE(free.starts_free);
  EXPECT_TRUE(chain_batchable(free, hht, options));
  // A stretched bar alone (no clamp) is refused too.
  Scene stretched = free_bar;
  stretched.bodies[0].displacement = {.left = 0.0, .right = 0.01};
  EXPECT_FALSE(chain_batchable(assemble(stretched), hht, options));

  // The free flight: filled in for the free bar until shortly before its closing at t = 1, never
  // for a scene that does not start free, even when its flag says it may.
  SimulationWorkspace ws;
  RunSummary summary;
  ASSERT_TRUE(prepare_run(free, options, ws.trace, ws.state, summary));
  EXPECT_GT(summary.skipped_steps, 10);
  AssembledScene forced = assemble(stretched);
  EXPECT_FALSE(forced.rigid_flight);
  forced.rigid_flight = true;
  ASSERT_TRUE(prepare_run(forced, options, ws.trace, ws.state, summary));
  EXPECT_EQ(summary.skipped_steps, 0);
  EXPECT_EQ(ws.state.u, forced.initial_displacement);  // the state at t = 0, not filled in
  forced = clamped;
  forced.rigid_flight = true;
  forced.first_contact_time = 1.0;
  ASSERT_TRUE(prepare_run(forced, options, ws.trace, ws.state, summary));
  EXPECT_EQ(summary.skipped_steps, 0);
}

}  // namespace
}  // namespace impactid
