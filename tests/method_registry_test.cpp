// The method registry (core/methods/method_registry.hpp): every method is registered once under its
// name; the parameters it takes build its parameter struct and are reported back unchanged; its
// defaults are default_params()'; a key it does not take is refused with the methods that do.
#include "core/methods/method_registry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

namespace impactid {
namespace {

constexpr MethodKind kEveryKind[] = {MethodKind::central_difference,
                                     MethodKind::backward_euler,
                                     MethodKind::newmark,
                                     MethodKind::hht,
                                     MethodKind::generalized_alpha,
                                     MethodKind::bathe,
                                     MethodKind::rho_bathe,
                                     MethodKind::tr_bdf2,
                                     MethodKind::houbolt,
                                     MethodKind::wilson_theta,
                                     MethodKind::noh_bathe,
                                     MethodKind::kim_explicit,
                                     MethodKind::kr_alpha};

TEST(MethodRegistry, EveryMethodIsRegisteredOnceUnderItsName) {
  ASSERT_EQ(method_registry().size(), std::size(kEveryKind));
  std::set<std::string> names;
  for (const MethodKind kind : kEveryKind) {
    const MethodDescriptor& m = descriptor(kind);
    EXPECT_EQ(m.kind, kind);
    EXPECT_TRUE(names.insert(m.name).second) << m.name;
    EXPECT_EQ(method_kind_from_string(m.name), kind);
    EXPECT_EQ(std::string(to_string(kind)), m.name);
    EXPECT_EQ(descriptor(default_params(kind)).kind, kind);
  }
  EXPECT_EQ(method_names(),
            "cdm|backward-euler|newmark|hht|generalized-alpha|bathe|rho-bathe|tr-bdf2|houbolt|"
            "wilson-theta|noh-bathe|kim-explicit|kr-alpha");
  EXPECT_FALSE(method_kind_from_string("rk4"));
}

TEST(MethodRegistry, EveryParameterIsAKeyOfTheTableAndTakenBySomeMethod) {
  std::set<std::string> taken;
  for (const MethodDescriptor& m : method_registry()) {
    for (const char* name : m.parameters) {
      EXPECT_TRUE(find_method_parameter(name)) << m.name << ": " << name;
      taken.insert(name);
    }
  }
  for (const MethodParameter& p : method_parameters()) {
    EXPECT_TRUE(taken.count(p.name)) << p.name << " is taken by no method";
    EXPECT_EQ(p.choice, *p.choices != '\0') << p.name;
  }
  EXPECT_EQ(methods_taking("delta"), "newmark|hht");
  EXPECT_EQ(methods_taking("hht_contact"), "hht|generalized-alpha");
}

// Nothing given: the method's defaults, reported as default_params() reports them.
TEST(MethodRegistry, NothingGivenIsTheMethodsDefaults) {
  for (const MethodKind kind : kEveryKind) {
    const auto built = build_method(kind, {});
    ASSERT_TRUE(std::holds_alternative<MethodParams>(built)) << to_string(kind);
    const MethodParams& p = std::get<MethodParams>(built);
    EXPECT_EQ(kind_of(p), kind);
    const auto a = descriptor(kind).values(p), b = descriptor(kind).values(default_params(kind));
    ASSERT_EQ(a.size(), b.size()) << to_string(kind);
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_STREQ(a[i].name, b[i].name);
      EXPECT_EQ(a[i].value, b[i].value) << to_string(kind) << " " << a[i].name;
    }
    EXPECT_FALSE(validate(p)) << to_string(kind);
  }
}

// Each number a method takes, given alone (Newmark's β with its γ), is reported back as given
// and is not marked derived; each choice word is reported back too.
TEST(MethodRegistry, GivenParametersAreReportedBackUnchanged) {
  const auto value_for = [](const std::string& name) {
    return name == "alpha"     ? -0.21
           : name == "rho_inf" ? 0.37
           : name == "gamma"   ? 0.61
           : name == "theta"   ? 1.55
           : name == "p"       ? 0.62
                               : 0.33;
  };
  int checked = 0;
  for (const MethodDescriptor& m : method_registry()) {
    for (const char* name : m.parameters) {
      const MethodParameter& info = *find_method_parameter(name);
      MethodArguments given;
      if (info.choice) {
        const std::string choices = info.choices;
        const std::string last = choices.substr(choices.rfind('|') + 1);
        given.set(name, last);
        const MethodParams p = std::get<MethodParams>(build_method(m.kind, given));
        bool found = false;
        for (const auto& [key, word] : m.choices(p)) {
          if (std::string(key) == name) found = word == last;
        }
        EXPECT_TRUE(found) << m.name << " " << name;
        ++checked;
        continue;
      }
      given.set(name, value_for(name));
      if (std::string(name) == "beta") given.set("gamma", value_for("gamma"));
      if (std::string(name) == "gamma") given.set("beta", value_for("beta"));
      const auto built = build_method(m.kind, given);
      ASSERT_TRUE(std::holds_alternative<MethodParams>(built)) << m.name << " " << name;
      const MethodParams& p = std::get<MethodParams>(built);
      EXPECT_EQ(reported_value(p, name), value_for(name)) << m.name << " " << name;
      for (const ReportedValue& v : m.values(p)) {
        if (std::string(v.name) == name) {
          EXPECT_FALSE(v.derived) << m.name << " " << name;
        }
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 15);  // every parameter of the thirteen methods
}

TEST(MethodRegistry, RefusesAKeyTheMethodDoesNotTakeOrABadCombination) {
  MethodArguments given;
  given.set("delta", 0.3);
  const auto e = std::get<ParameterError>(build_method(MethodKind::central_difference, given));
  EXPECT_EQ(e.field, "delta");
  EXPECT_EQ(e.value, "0.3");
  EXPECT_EQ(e.constraint, "is not a parameter of method cdm (it applies to newmark|hht)");

  given.set("beta", 0.3);
  const auto both = std::get<ParameterError>(build_method(MethodKind::newmark, given));
  EXPECT_EQ(both.field, "delta");
  MethodArguments beta;
  beta.set("beta", 0.3);
  EXPECT_EQ(std::get<ParameterError>(build_method(MethodKind::newmark, beta)).field, "gamma");

  MethodArguments word;
  word.set("hht_contact", std::string("sideways"));
  const auto bad = std::get<ParameterError>(build_method(MethodKind::hht, word));
  EXPECT_EQ(bad.field, "hht_contact");
  EXPECT_EQ(bad.constraint, "must be one of endpoint|weighted");
}

// ρ∞-Bathe's ranges: ρ∞ in [0, 1], the sub-step ratio in (0, 1) with both ends excluded.
TEST(MethodRegistry, RhoBatheRangesAreCheckedByName) {
  for (const double gamma : {0.0, 1.0, 1.2, -0.1}) {
    const auto e = validate(RhoBatheParams{.rho_inf = 0.5, .gamma = gamma});
    ASSERT_TRUE(e) << gamma;
    EXPECT_EQ(e->field, "substep_ratio");
    EXPECT_EQ(e->constraint, "must lie in (0, 1), both ends excluded");
  }
  const auto e = validate(RhoBatheParams{.rho_inf = 1.5});
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "rho_inf");
  EXPECT_FALSE(validate(RhoBatheParams{.rho_inf = 1.0, .gamma = 0.5}));
}

// Wilson-θ's θ: unconditionally stable from (1 + √3)/2 on (tests/wilson_theta_test.cpp measures
// both sides), so anything below, or not finite, is refused by name; a key of another method is
// refused with the methods that take it, and θ with the one that does.
TEST(MethodRegistry, WilsonThetaRangeIsCheckedByName) {
  for (const double theta : {1.0, 1.3, 1.366, -2.0, std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN()}) {
    const auto e = validate(WilsonThetaParams{.theta = theta});
    ASSERT_TRUE(e) << theta;
    EXPECT_EQ(e->field, "theta");
    EXPECT_EQ(e->value, format_value(theta));
    EXPECT_EQ(e->constraint,
              "must be >= (1+sqrt(3))/2 = 1.3660254 (unconditional stability) and finite");
  }
  for (const double theta : {kWilsonThetaMinimum, 1.37, 1.4, 2.0, 10.0}) {
    EXPECT_FALSE(validate(WilsonThetaParams{.theta = theta})) << theta;
  }
  EXPECT_NEAR(kWilsonThetaMinimum, (1.0 + std::sqrt(3.0)) / 2.0, 1e-16);
  EXPECT_EQ(std::get<WilsonThetaParams>(default_params(MethodKind::wilson_theta)).theta, 1.4);

  MethodArguments theta;
  theta.set("theta", 1.2);
  const auto built = build_method(MethodKind::wilson_theta, theta);
  ASSERT_TRUE(std::holds_alternative<MethodParams>(built));
  EXPECT_EQ(*reported_value(std::get<MethodParams>(built), "theta"), 1.2);
  EXPECT_EQ(validate(std::get<MethodParams>(built))->field, "theta");
  const auto refused = std::get<ParameterError>(build_method(MethodKind::houbolt, theta));
  EXPECT_EQ(refused.field, "theta");
  EXPECT_EQ(refused.value, "1.2");
  EXPECT_EQ(refused.constraint,
            "is not a parameter of method houbolt (it applies to wilson-theta)");
  MethodArguments delta;
  delta.set("delta", 0.3);
  EXPECT_EQ(std::get<ParameterError>(build_method(MethodKind::wilson_theta, delta)).constraint,
            "is not a parameter of method wilson-theta (it applies to newmark|hht)");
  EXPECT_EQ(methods_taking("theta"), "wilson-theta");
}

// HHT's δ defaults to −α (eq. 15) and is reported so; β and γ follow eq. 13 and are derived.
TEST(MethodRegistry, HhtReportsItsDefaultDeltaAndDerivedCoefficients) {
  MethodArguments given;
  given.set("alpha", -0.2);
  const MethodParams p = std::get<MethodParams>(build_method(MethodKind::hht, given));
  EXPECT_DOUBLE_EQ(*reported_value(p, "delta"), 0.2);
  EXPECT_DOUBLE_EQ(*reported_value(p, "beta"), 0.25 * 1.2 * 1.2);
  EXPECT_DOUBLE_EQ(*reported_value(p, "gamma"), 0.7);
  EXPECT_FALSE(reported_value(p, "rho_inf"));
}

}  // namespace
}  // namespace impactid
