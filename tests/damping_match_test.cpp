// Matching the algorithmic damping ratio across method families, and the shipped plan
// plans/identical-dissipation.toml held to its definition: every adjustable method at the ξ̄ of
// HHT (α = −0.3, δ = 0.45) at Ω = ω·Δt = 1, the highest mode of the default rod.
#include "study/studies/damping_match.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>

#include "core/methods/implicit_integrator.hpp"
#include "core/spectral/amplification.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

// A family by its name (registered by its method).
DampingFamily named_family(const char* name) {
  return *find_damping_family(name);
}

double xi(const MethodParams& params, double omega_dt) {
  return spectral_properties(params, omega_dt).damping_ratio;
}

// ξ̄ measured independently of core/spectral/amplification: one step of ImplicitIntegrator on
// ü + u = 0 from each unit state (u, Δt·v, Δt²·a) gives the amplification matrix column by
// column; its complex pair a ± ib gives ξ̄ = −ln(a² + b²)/(2·atan2(b, a)).
double stepped_damping_ratio(const MethodParams& params, double dt) {
  const Eigen::Matrix3d amplification =
      testing::stepped_amplification(implicit_coefficients(params), dt);
  if (std::isnan(amplification(0, 0))) return NAN;  // the integrator did not initialize
  for (const std::complex<double>& lambda : testing::eigenvalues(amplification)) {
    if (lambda.imag() > 1e-12) {
      return -std::log(std::norm(lambda)) / (2.0 * std::atan2(lambda.imag(), lambda.real()));
    }
  }
  return NAN;
}

TEST(DampingMatch, EveryFamilyHitsAReachableTarget) {
  // Targets within every family's range but HHT eq. 15's (too little damping: below).
  for (const auto& [omega, target] : {std::pair{0.3, 0.008}, {1.0, 0.05}, {3.0, 0.15}}) {
    for (const DampingFamilyInfo& f : damping_families()) {
      // HHT eq. 15, ρ∞-Bathe and the two-stage explicit schemes damp too little at these Ω,
      // Wilson-θ too much at Ω = 0.3 (their own tests below).
      if (f.family == named_family("hht-eq15") || f.family == named_family("rho-bathe") ||
          f.family == named_family("noh-bathe") || f.family == named_family("kim-explicit") ||
          f.family == named_family("wilson-theta")) {
        continue;
      }
      SCOPED_TRACE(std::string(f.name) + " at omega*dt = " + std::to_string(omega));
      const DampingMatch m = match_damping(f.family, omega, target);
      ASSERT_TRUE(m.reachable);
      EXPECT_EQ(m.roots, 1);
      EXPECT_GE(m.parameter, std::min(f.undamped_end, f.damped_end));
      EXPECT_LE(m.parameter, std::max(f.undamped_end, f.damped_end));
      EXPECT_NEAR(m.damping_ratio, target, 1e-14);
      EXPECT_EQ(m.damping_ratio, xi(family_params(f.family, m.parameter), omega));
      // The integrator itself damps the mode at that rate (the single-step implicit ones; KR-α's
      // stepper is held to its amplification matrix by tests/kr_alpha_test.cpp).
      if (f.family != named_family("kr-alpha")) {
        EXPECT_NEAR(stepped_damping_ratio(family_params(f.family, m.parameter), omega), target,
                    1e-9);
      }
      EXPECT_LE(m.attainable_min, target);
      EXPECT_GE(m.attainable_max, target);
    }
  }
}

TEST(DampingMatch, KnownAnswers) {
  // Newmark with delta = 1 has backward Euler's damping ratio (docs/methods.md: the same
  // displacements), so matching backward Euler gives delta = 1.
  const double be = xi(BackwardEulerParams{}, 1.0);
  const DampingMatch newmark = match_damping(named_family("newmark"), 1.0, be);
  ASSERT_TRUE(newmark.reachable);
  EXPECT_NEAR(newmark.parameter, 1.0, 1e-12);
  // HHT on eq. 19 matched to its own point returns that point.
  const double hht = xi(HhtParams{.alpha = -0.3, .delta = 0.45}, 1.0);
  const DampingMatch eq19 = match_damping(named_family("hht-eq19"), 1.0, hht);
  ASSERT_TRUE(eq19.reachable);
  EXPECT_NEAR(eq19.parameter, -0.3, 1e-14);
  // No damping: the undamped end, exactly.
  EXPECT_EQ(match_damping(named_family("newmark"), 1.0, 0.0).parameter, 0.0);
  EXPECT_EQ(match_damping(named_family("hht-eq19"), 1.0, 0.0).parameter, 0.0);
}

TEST(DampingMatch, OutOfRangeIsNotReachableAndSaysWhatIs) {
  // HHT with delta = -alpha damps little: xi(1) stays near 0.012 at most.
  const DampingMatch m = match_damping(named_family("hht-eq15"), 1.0, 0.05);
  EXPECT_FALSE(m.reachable);
  EXPECT_EQ(m.roots, 0);
  EXPECT_TRUE(std::isnan(m.parameter));
  EXPECT_EQ(m.attainable_min, 0.0);
  EXPECT_GT(m.attainable_max, 0.011);
  EXPECT_LT(m.attainable_max, 0.0125);
  // Generalized-alpha cannot exceed rho_inf = 0's damping.
  const DampingMatch ga = match_damping(named_family("generalized-alpha"), 1.0, 0.5);
  EXPECT_FALSE(ga.reachable);
  EXPECT_NEAR(ga.attainable_max, xi(GeneralizedAlphaParams{.rho_inf = 0.0}, 1.0), 1e-15);
  // Invalid input.
  EXPECT_FALSE(match_damping(named_family("newmark"), 0.0, 0.1).reachable);
  EXPECT_FALSE(match_damping(named_family("newmark"), NAN, 0.1).reachable);
  EXPECT_FALSE(match_damping(named_family("newmark"), 1.0, NAN).reachable);
}

TEST(DampingMatch, NonMonotoneFamilyReturnsTheLeastDissipativeRoot) {
  // xi(1) of HHT with delta = -alpha rises to a maximum near alpha = -1/3 and falls again.
  const double target = 0.0115;
  const DampingMatch m = match_damping(named_family("hht-eq15"), 1.0, target);
  ASSERT_TRUE(m.reachable);
  EXPECT_EQ(m.roots, 2);
  EXPECT_GT(m.parameter, -1.0 / 3.0);  // the root on the alpha = 0 side
  EXPECT_NEAR(m.damping_ratio, target, 1e-14);
}

// ---- plans/identical-dissipation.toml ------------------------------------------------------

TEST(ShippedPlans, IdenticalDissipationMatchesItsDefinition) {
  const Plan plan =
      load_plan(std::filesystem::path(IMPACTID_SOURCE_DIR) / "plans/identical-dissipation.toml");
  ASSERT_EQ(plan.kind, StudyKind::list);
  ASSERT_TRUE(plan.output.histories.has_value());
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 12);

  std::vector<Simulation> sims;
  for (long k = 0; k < points.size(); ++k) {
    sims.push_back(std::get<Simulation>(build(points.settings(k))));
  }
  // The reference: HHT on eq. 19 at alpha = -0.3.
  const auto* reference = std::get_if<HhtParams>(&sims[0].method);
  ASSERT_NE(reference, nullptr);
  EXPECT_EQ(reference->alpha, -0.3);
  EXPECT_EQ(reference->delta, 0.45);

  std::vector<MethodKind> kinds;
  for (const Simulation& sim : sims) {
    kinds.push_back(kind_of(sim.method));
    // Omega = 1 is the highest mode of each point's own rod: 2*Courant with a lumped mass.
    const RodSceneDerived d = derive(*sim.rod());
    const double courant = d.time_step * d.wave_speed / d.element_length;
    EXPECT_NEAR(rod_max_omega_dt(sim.rod()->mass, courant), 1.0, 1e-12);
  }
  for (const MethodKind kind :
       {MethodKind::central_difference, MethodKind::backward_euler, MethodKind::newmark,
        MethodKind::hht, MethodKind::generalized_alpha, MethodKind::bathe, MethodKind::rho_bathe,
        MethodKind::houbolt, MethodKind::wilson_theta, MethodKind::noh_bathe,
        MethodKind::kim_explicit, MethodKind::kr_alpha}) {
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), kind), kinds.end()) << to_string(kind);
  }

  const double target = xi(sims[0].method, 1.0);
  int matched = 0;
  for (const Simulation& sim : sims) {
    const MethodKind kind = kind_of(sim.method);
    if (kind == MethodKind::backward_euler || kind == MethodKind::central_difference ||
        kind == MethodKind::houbolt || kind == MethodKind::bathe) {
      continue;  // no parameter: their own damping
    }
    SCOPED_TRACE(to_string(kind));
    // Out of reach: the family's most damped member at Ω = 1 (ρ∞-Bathe's at ρ∞ = 0, the end of
    // its range; Noh–Bathe's at the scan's maximum, p = 0.6666; Kim's at p = ½).
    const auto out_of_reach = [&](DampingFamily family) {
      const DampingMatch m = match_damping(family, 1.0, target);
      EXPECT_FALSE(m.reachable);
      EXPECT_EQ(xi(sim.method, 1.0), m.attainable_max);
    };
    if (kind == MethodKind::rho_bathe) {
      out_of_reach(named_family("rho-bathe"));
    } else if (kind == MethodKind::noh_bathe) {
      out_of_reach(named_family("noh-bathe"));
    } else if (kind == MethodKind::kim_explicit) {
      out_of_reach(named_family("kim-explicit"));
    } else {
      EXPECT_NEAR(xi(sim.method, 1.0), target, 1e-6 * target);
      if (kind != MethodKind::kr_alpha && kind != MethodKind::wilson_theta) {
        EXPECT_NEAR(stepped_damping_ratio(sim.method, 1.0), target, 1e-6 * target);
      }
      ++matched;
    }
  }
  // hht (the reference), newmark, generalized-alpha, kr-alpha, wilson-theta
  EXPECT_EQ(matched, 5);
  // HHT with delta = -alpha is left out because it cannot reach the target.
  EXPECT_FALSE(match_damping(named_family("hht-eq15"), 1.0, target).reachable);
}

// ρ∞-Bathe concentrates its damping at high Ω: at Ω = 1 it reaches at most the ξ̄ of ρ∞ = 0,
// 0.0033, so HHT's ξ̄(1) = 0.071 of plans/identical-dissipation.toml is out of its reach; a
// target within its range is matched, and the match is its ξ̄.
TEST(DampingMatch, RhoBatheDampsLittleAtOmegaDtOne) {
  const DampingMatch far = match_damping(named_family("rho-bathe"), 1.0, 0.07137500541822885);
  EXPECT_FALSE(far.reachable);
  EXPECT_NEAR(far.attainable_max, xi(RhoBatheParams{.rho_inf = 0.0}, 1.0), 1e-15);
  EXPECT_LT(far.attainable_max, 0.004);
  const DampingMatch m = match_damping(named_family("rho-bathe"), 1.0, 0.002);
  ASSERT_TRUE(m.reachable);
  EXPECT_GT(m.parameter, 0.0);
  EXPECT_LT(m.parameter, 1.0);
  EXPECT_NEAR(m.damping_ratio, 0.002, 1e-14);
  EXPECT_EQ(m.damping_ratio, xi(RhoBatheParams{.rho_inf = m.parameter}, 1.0));
  // At Ω = 3 it does reach 0.15's neighbourhood from below: its range grows with Ω.
  EXPECT_GT(match_damping(named_family("rho-bathe"), 3.0, 0.01).attainable_max, 0.01);
}

// KR-α's characteristic polynomial is generalized-α's (tests/kr_alpha_test.cpp), so the two
// families match any target at the same ρ∞ (up to the rounding of two different matrices).
TEST(DampingMatch, KrAlphaMatchesAtGeneralizedAlphasRhoInf) {
  for (const auto& [omega, target] :
       {std::pair{0.3, 0.008}, {1.0, 0.07137500541822885}, {3.0, 0.15}}) {
    const DampingMatch kr = match_damping(named_family("kr-alpha"), omega, target);
    const DampingMatch ga = match_damping(named_family("generalized-alpha"), omega, target);
    ASSERT_TRUE(kr.reachable);
    ASSERT_TRUE(ga.reachable);
    EXPECT_NEAR(kr.parameter, ga.parameter, 1e-9);
  }
}

// Wilson-θ damps at every θ of its stable range, most weakly at its bound (1 + √3)/2: a target
// below that end's ξ̄ is out of reach, HHT's ξ̄(1) of plans/identical-dissipation.toml is not.
TEST(DampingMatch, WilsonThetaHasAFloorOfDamping) {
  const double floor = xi(WilsonThetaParams{.theta = 1.3660254037844386}, 1.0);
  EXPECT_GT(floor, 0.03);
  const DampingMatch low = match_damping(named_family("wilson-theta"), 1.0, 0.5 * floor);
  EXPECT_FALSE(low.reachable);
  EXPECT_EQ(low.attainable_min, floor);
  const DampingMatch m = match_damping(named_family("wilson-theta"), 1.0, 0.07137500541822885);
  ASSERT_TRUE(m.reachable);
  EXPECT_EQ(m.roots, 1);
  EXPECT_GT(m.parameter, 1.37);
  EXPECT_LT(m.parameter, 2.0);
  EXPECT_NEAR(m.damping_ratio, 0.07137500541822885, 1e-14);
}

// The two-stage explicit schemes damp little at Ω = 1 (below 0.01: Noh–Bathe's p has no
// dissipation at ½ and its ξ̄(1) peaks near p = 0.6; Kim's grows from p = ⅓ to ½), so HHT's 0.071
// is out of their reach; a target within their range is matched.
TEST(DampingMatch, TwoStageExplicitSchemesDampLittleAtOmegaDtOne) {
  for (const DampingFamily family : {named_family("noh-bathe"), named_family("kim-explicit")}) {
    SCOPED_TRACE(family_info(family).name);
    const DampingMatch far = match_damping(family, 1.0, 0.07137500541822885);
    EXPECT_FALSE(far.reachable);
    EXPECT_LT(far.attainable_max, 0.01);
    const double target = 0.5 * far.attainable_max;
    const DampingMatch m = match_damping(family, 1.0, target);
    ASSERT_TRUE(m.reachable);
    EXPECT_NEAR(m.damping_ratio, target, 1e-14);
    EXPECT_EQ(m.damping_ratio, xi(family_params(family, m.parameter), 1.0));
  }
  // Noh–Bathe's ξ̄(1) rises from p = ½ and falls again: two roots, the one nearer ½ returned.
  const DampingMatch nb = match_damping(named_family("noh-bathe"), 1.0, 0.001);
  EXPECT_EQ(nb.roots, 2);
  EXPECT_LT(nb.parameter, 0.54);
}

}  // namespace
}  // namespace impactid
