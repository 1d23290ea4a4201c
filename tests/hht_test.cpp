// HHT-α (eqs 14–15): reduces to Newmark at α = 0, damps high frequencies to the known spectral
// radius (1+α)/(1−α) with eq. 15, and is unstable when δ < −α.
#include <gtest/gtest.h>

#include <cmath>

#include "core/methods/method.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

using testing::max_abs_difference;
using testing::run;
using testing::spectral_radius;

// α = 0 removes the α-weighting of eq. 14: HHT must then be Newmark with the same δ, contact
// included, or the HHT sweep's α = 0 edge would not join the Newmark results.
TEST(Hht, AlphaZeroEqualsNewmarkWithSameDelta) {
  const RodScene scene;
  const double p_scale = derive(scene).pressure_scale;
  for (double delta : {0.0, 0.3, 0.6}) {
    // δ = 0 chatters on the wall and grows the energy (method.hpp); compare it all the same.
    const RunOptions options = testing::stepping_options(1e6);
    for (ContactWeighting weighting : {ContactWeighting::endpoint, ContactWeighting::weighted}) {
      const testing::Run hht =
          run(scene, HhtParams{.alpha = 0.0, .delta = delta, .contact = weighting}, options);
      const testing::Run newmark = run(scene, NewmarkParams{.delta = delta}, options);
      ASSERT_EQ(hht.summary.status, newmark.summary.status) << delta;
      ASSERT_EQ(hht.summary.status, RunStatus::ok) << delta;
      EXPECT_LE(max_abs_difference(hht.trace.pressure, newmark.trace.pressure), 1e-12 * p_scale)
          << "δ = " << delta << ", " << to_string(weighting);
      EXPECT_LE(max_abs_difference(hht.trace.velocity, newmark.trace.velocity),
                1e-12 * scene.velocity)
          << "δ = " << delta << ", " << to_string(weighting);
    }
  }
}

// With eq. 15, HHT's spectral radius at Ω → ∞ is (1+α)/(1−α) (Hilber, Hughes & Taylor 1977):
// the amount of high-frequency damping α is meant to control.
// At α = −1/3 all three roots meet as Ω → ∞, and the computed radius converges slowly (7.8e-5
// off at Ω = 1e6): evaluate far out, at Ω = 1e9.
TEST(Hht, HighFrequencySpectralRadius) {
  for (double alpha : {-0.05, -0.1, -0.2, -0.3, -1.0 / 3.0}) {
    const double expected = (1 + alpha) / (1 - alpha);
    EXPECT_NEAR(spectral_radius(implicit_coefficients(HhtParams{.alpha = alpha}), 1e9), expected,
                1e-4)
        << alpha;
  }
  // And no damping at the low end: ρ → 1 as Ω → 0.
  EXPECT_NEAR(spectral_radius(implicit_coefficients(HhtParams{.alpha = -0.3}), 1e-3), 1.0, 1e-6);
}

// Unconditional stability for δ >= −α, instability for δ < −α: ρ(Ω) over six decades of Ω.
TEST(Hht, SpectralRadiusExceedsOneOnlyWhenDeltaBelowMinusAlpha) {
  const auto worst = [](const HhtParams& p) {
    double r = 0.0;
    for (double omega = 1e-2; omega <= 1e4; omega *= 1.25) {
      r = std::max(r, spectral_radius(implicit_coefficients(p), omega));
    }
    return r;
  };
  // 1 + round-off of the computed eigenvalues (coalescing roots: of order ε^(1/3)).
  EXPECT_LE(worst(HhtParams{.alpha = -0.3}), 1.0 + 1e-6);
  EXPECT_LE(worst(HhtParams{.alpha = -0.3, .delta = 0.45}), 1.0 + 1e-6);
  EXPECT_LE(worst(HhtParams{.alpha = -0.5, .delta = 0.5}), 1.0 + 1e-6);
  // Measured maxima: 1.41 near Ω ≈ 4 and 1.03 near Ω ≈ 1.4.
  EXPECT_GT(worst(HhtParams{.alpha = -0.5, .delta = 0.0}), 1.1);
  EXPECT_GT(worst(HhtParams{.alpha = -0.3, .delta = 0.2}), 1.01);
}

}  // namespace
}  // namespace impactid
