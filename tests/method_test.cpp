// Method parameters: validation, the coefficient formulas of eqs 13 and 15 and of Chung &
// Hulbert, and the string names shared by the CLI, plan files and HDF5.
#include "core/methods/method.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace impactid {
namespace {

constexpr MethodKind kAllKinds[] = {MethodKind::central_difference, MethodKind::backward_euler,
                                    MethodKind::newmark, MethodKind::hht,
                                    MethodKind::generalized_alpha};

// A plan point with a bad parameter must be rejected, never run as something else.
TEST(MethodValidation, RejectsOutOfRangeParametersNamingTheField) {
  EXPECT_EQ(validate(NewmarkParams{.delta = -0.1})->field, "delta");
  EXPECT_EQ(validate(NewmarkParams{.delta = std::numeric_limits<double>::quiet_NaN()})->field,
            "delta");
  EXPECT_EQ(validate(HhtParams{.alpha = -0.7})->field, "alpha");
  EXPECT_EQ(validate(HhtParams{.alpha = 0.1})->field, "alpha");
  EXPECT_EQ(validate(HhtParams{.alpha = -0.3, .delta = -0.1})->field, "delta");
  EXPECT_EQ(validate(GeneralizedAlphaParams{.rho_inf = 1.5})->field, "rho_inf");
  EXPECT_EQ(validate(GeneralizedAlphaParams{.rho_inf = -0.1})->field, "rho_inf");
  EXPECT_EQ(validate(NewmarkParams{.coefficients = BetaGamma{0.0, 0.5}})->field, "beta");
  EXPECT_EQ(validate(NewmarkParams{.coefficients = BetaGamma{0.25, -0.5}})->field, "gamma");

  const auto error = validate(HhtParams{.alpha = -0.7});
  EXPECT_EQ(error->value, "-0.7");
  EXPECT_FALSE(error->constraint.empty());
}

// The interval ends are part of the documented ranges.
TEST(MethodValidation, AcceptsDefaultsAndRangeEnds) {
  for (MethodKind kind : kAllKinds) {
    EXPECT_FALSE(validate(default_params(kind)).has_value()) << to_string(kind);
  }
  EXPECT_FALSE(validate(NewmarkParams{.delta = 0.0}).has_value());
  EXPECT_FALSE(validate(HhtParams{.alpha = -0.5}).has_value());
  EXPECT_FALSE(validate(HhtParams{.alpha = 0.0, .delta = 0.0}).has_value());
  EXPECT_FALSE(validate(GeneralizedAlphaParams{.rho_inf = 0.0}).has_value());
  EXPECT_FALSE(validate(GeneralizedAlphaParams{.rho_inf = 1.0}).has_value());
  // δ < −α is unstable but legal: the study maps that region on purpose.
  EXPECT_FALSE(validate(HhtParams{.alpha = -0.5, .delta = 0.0}).has_value());
}

// Eq. 13: β = (1+δ)²/4, γ = 1/2 + δ; worked by hand.
TEST(MethodCoefficients, NewmarkFromDeltaIsEquation13) {
  EXPECT_DOUBLE_EQ(newmark_from_delta(0.0).beta, 0.25);
  EXPECT_DOUBLE_EQ(newmark_from_delta(0.0).gamma, 0.5);
  EXPECT_DOUBLE_EQ(newmark_from_delta(0.3).beta, 0.4225);
  EXPECT_DOUBLE_EQ(newmark_from_delta(0.3).gamma, 0.8);
  EXPECT_DOUBLE_EQ(newmark_from_delta(1.0).beta, 1.0);
  EXPECT_DOUBLE_EQ(newmark_from_delta(1.0).gamma, 1.5);
}

// The Newmark family in the integrator's (b0, b1, g0, g1) form: b0 = ½−β, g0 = 1−γ (eqs 11–12).
TEST(MethodCoefficients, NewmarkDeltaAndExplicitForms) {
  const ImplicitCoefficients d = implicit_coefficients(NewmarkParams{.delta = 0.3});
  EXPECT_DOUBLE_EQ(d.b1, 0.4225);
  EXPECT_DOUBLE_EQ(d.b0, 0.5 - 0.4225);
  EXPECT_DOUBLE_EQ(d.g1, 0.8);
  EXPECT_DOUBLE_EQ(d.g0, 1.0 - 0.8);
  EXPECT_EQ(d.alpha_m, 0.0);
  EXPECT_EQ(d.alpha_f, 0.0);
  EXPECT_EQ(d.contact_weight, 1.0);

  const ImplicitCoefficients e =
      implicit_coefficients(NewmarkParams{.delta = 0.9, .coefficients = BetaGamma{0.3, 0.6}});
  EXPECT_DOUBLE_EQ(e.b1, 0.3);  // explicit coefficients replace δ entirely
  EXPECT_DOUBLE_EQ(e.b0, 0.2);
  EXPECT_DOUBLE_EQ(e.g1, 0.6);
  EXPECT_DOUBLE_EQ(e.g0, 0.4);
}

// Eq. 15: with δ unset HHT is the second-order member, β = (1−α)²/4, γ = (1−2α)/2.
TEST(MethodCoefficients, HhtDefaultDeltaIsEquation15) {
  for (double alpha : {0.0, -0.1, -0.3, -1.0 / 3.0, -0.5}) {
    const ImplicitCoefficients c = implicit_coefficients(HhtParams{.alpha = alpha});
    EXPECT_DOUBLE_EQ(c.b1, (1 - alpha) * (1 - alpha) / 4) << alpha;
    EXPECT_DOUBLE_EQ(c.g1, (1 - 2 * alpha) / 2) << alpha;
    EXPECT_DOUBLE_EQ(c.b0 + c.b1, 0.5) << alpha;
    EXPECT_DOUBLE_EQ(c.g0 + c.g1, 1.0) << alpha;
    EXPECT_DOUBLE_EQ(c.alpha_f, -alpha) << alpha;  // Chung & Hulbert's α_f = −α
    EXPECT_EQ(c.alpha_m, 0.0);
  }
  // With δ given, eq. 13 is used with that δ, independently of α.
  const ImplicitCoefficients c = implicit_coefficients(HhtParams{.alpha = -0.3, .delta = 0.45});
  EXPECT_DOUBLE_EQ(c.b1, 1.45 * 1.45 / 4);
  EXPECT_DOUBLE_EQ(c.g1, 0.95);
  EXPECT_DOUBLE_EQ(c.alpha_f, 0.3);
}

// Weighted contact acts like the elastic force: weight 1 − α_f on λ_{t+Δt}.
TEST(MethodCoefficients, ContactWeight) {
  EXPECT_EQ(implicit_coefficients(HhtParams{.alpha = -0.3}).contact_weight, 1.0);
  EXPECT_DOUBLE_EQ(
      implicit_coefficients(HhtParams{.alpha = -0.3, .contact = ContactWeighting::weighted})
          .contact_weight,
      0.7);
  EXPECT_DOUBLE_EQ(implicit_coefficients(GeneralizedAlphaParams{
                                             .rho_inf = 1.0, .contact = ContactWeighting::weighted})
                       .contact_weight,
                   0.5);
}

// Backward Euler (eqs 8–9): u₁ = u₀ + Δt·v₁, v₁ = v₀ + Δt·a₁, i.e. b0 = g0 = 0, b1 = g1 = 1.
TEST(MethodCoefficients, BackwardEuler) {
  const ImplicitCoefficients c = implicit_coefficients(BackwardEulerParams{});
  EXPECT_EQ(c.b0, 0.0);
  EXPECT_EQ(c.b1, 1.0);
  EXPECT_EQ(c.g0, 0.0);
  EXPECT_EQ(c.g1, 1.0);
  EXPECT_EQ(c.alpha_m, 0.0);
  EXPECT_EQ(c.alpha_f, 0.0);
}

// Chung & Hulbert (1993) eqs 25 and 17, worked by hand at ρ∞ = 1, 0.5 and 0.
TEST(MethodCoefficients, GeneralizedAlphaFromRhoInf) {
  const ImplicitCoefficients one = implicit_coefficients(GeneralizedAlphaParams{.rho_inf = 1.0});
  EXPECT_DOUBLE_EQ(one.alpha_m, 0.5);
  EXPECT_DOUBLE_EQ(one.alpha_f, 0.5);
  EXPECT_DOUBLE_EQ(one.g1, 0.5);
  EXPECT_DOUBLE_EQ(one.b1, 0.25);

  // ρ∞ = 1/2: α_m = 0, α_f = 1/3, γ = 5/6, β = (4/3)²/4 = 4/9.
  const ImplicitCoefficients half = implicit_coefficients(GeneralizedAlphaParams{.rho_inf = 0.5});
  EXPECT_NEAR(half.alpha_m, 0.0, 1e-16);
  EXPECT_DOUBLE_EQ(half.alpha_f, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(half.g1, 5.0 / 6.0);
  EXPECT_DOUBLE_EQ(half.b1, 4.0 / 9.0);

  // ρ∞ = 0: α_m = −1, α_f = 0, γ = 3/2, β = 1.
  const ImplicitCoefficients zero = implicit_coefficients(GeneralizedAlphaParams{.rho_inf = 0.0});
  EXPECT_DOUBLE_EQ(zero.alpha_m, -1.0);
  EXPECT_DOUBLE_EQ(zero.alpha_f, 0.0);
  EXPECT_DOUBLE_EQ(zero.g1, 1.5);
  EXPECT_DOUBLE_EQ(zero.b1, 1.0);
}

// Reports show β, γ only where the method has them.
TEST(MethodCoefficients, ReportedBetaGamma) {
  EXPECT_FALSE(reported_beta_gamma(CentralDifferenceParams{}).has_value());
  EXPECT_FALSE(reported_beta_gamma(BackwardEulerParams{}).has_value());
  const auto bg = reported_beta_gamma(NewmarkParams{.delta = 0.3});
  ASSERT_TRUE(bg.has_value());
  EXPECT_DOUBLE_EQ(bg->beta, 0.4225);
  EXPECT_DOUBLE_EQ(bg->gamma, 0.8);
}

// One conversion table for CLI, plans and HDF5 (habit 6): names must not drift.
TEST(MethodNames, RoundTripAndExactSpelling) {
  EXPECT_STREQ(to_string(MethodKind::central_difference), "cdm");
  EXPECT_STREQ(to_string(MethodKind::backward_euler), "backward-euler");
  EXPECT_STREQ(to_string(MethodKind::newmark), "newmark");
  EXPECT_STREQ(to_string(MethodKind::hht), "hht");
  EXPECT_STREQ(to_string(MethodKind::generalized_alpha), "generalized-alpha");
  for (MethodKind kind : kAllKinds) {
    EXPECT_EQ(method_kind_from_string(to_string(kind)), kind);
    EXPECT_EQ(kind_of(default_params(kind)), kind);
  }
  EXPECT_FALSE(method_kind_from_string("backward_euler").has_value());
  EXPECT_FALSE(method_kind_from_string("HHT").has_value());
  EXPECT_FALSE(method_kind_from_string("").has_value());

  for (CdmVelocity v : {CdmVelocity::central, CdmVelocity::backward}) {
    EXPECT_EQ(cdm_velocity_from_string(to_string(v)), v);
  }
  for (ContactWeighting w : {ContactWeighting::endpoint, ContactWeighting::weighted}) {
    EXPECT_EQ(contact_weighting_from_string(to_string(w)), w);
  }
  EXPECT_FALSE(cdm_velocity_from_string("forward").has_value());
  EXPECT_FALSE(contact_weighting_from_string("mean").has_value());
}

// The documented defaults (δ = 0.3, α = −0.3 with δ = −α, ρ∞ = 0.8, endpoint contact).
TEST(MethodDefaults, MatchTheHeader) {
  EXPECT_DOUBLE_EQ(std::get<NewmarkParams>(default_params(MethodKind::newmark)).delta, 0.3);
  const auto hht = std::get<HhtParams>(default_params(MethodKind::hht));
  EXPECT_DOUBLE_EQ(hht.alpha, -0.3);
  EXPECT_FALSE(hht.delta.has_value());
  EXPECT_EQ(hht.contact, ContactWeighting::endpoint);
  EXPECT_DOUBLE_EQ(
      std::get<GeneralizedAlphaParams>(default_params(MethodKind::generalized_alpha)).rho_inf,
      0.8);
  EXPECT_EQ(std::get<CentralDifferenceParams>(default_params(MethodKind::central_difference))
                .velocity,
            CdmVelocity::central);
}

}  // namespace
}  // namespace impactid
