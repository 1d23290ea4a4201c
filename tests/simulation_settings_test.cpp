// The parameter table is the one source of names, defaults and errors for the command line,
// plan files and sweep axes; these tests keep its text honest against the code.
#include "study/plan/simulation_settings.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

namespace impactid {
namespace {

Simulation built(const SimulationSettings& s) {
  auto result = build(s);
  if (auto* e = std::get_if<ParameterError>(&result)) {
    ADD_FAILURE() << e->field << " = " << e->value << ": " << e->constraint;
    return {};
  }
  return std::get<Simulation>(result);
}

ParameterError error_of(const SimulationSettings& s) {
  auto result = build(s);
  EXPECT_TRUE(std::holds_alternative<ParameterError>(result));
  return std::holds_alternative<ParameterError>(result) ? std::get<ParameterError>(result)
                                                        : ParameterError{};
}

// Every "(default X" written in a description must be the value the code uses, for a method
// that takes the parameter: documentation that drifts from the code is a defect.
TEST(SimulationSettings, DocumentedDefaultsAreTheCodeDefaults) {
  const std::regex default_number(R"(default (-?[0-9.]+(e-?[0-9]+)?))");
  int checked = 0;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.kind == ParameterKind::choice) continue;
    std::string description = info.description;
    std::smatch match;
    if (!std::regex_search(description, match, default_number)) continue;
    const double documented = std::stod(match[1]);
    SimulationSettings settings;
    if (*info.methods) {
      const std::string_view methods = info.methods;
      const std::string first(methods.substr(0, methods.find('|')));
      settings.method.kind = *method_kind_from_string(first);
    }
    const std::string_view name = info.name;
    if (name == "reference_tolerance" || name == "reference_max_refinements") {  // bodies' own
      Scene bodies;
      bodies.bodies = {Body{.name = "a", .velocity = 1.0, .segments = {Segment{}}},
                       Body{.name = "b", .gap = 0.1, .segments = {Segment{}}}};
      settings.bodies = bodies;
    }
    const auto actual = numeric_value(built(settings), info.name);
    ASSERT_TRUE(actual.has_value()) << info.name;
    EXPECT_DOUBLE_EQ(*actual, documented) << info.name << ": " << info.description;
    ++checked;
  }
  EXPECT_GE(checked, 12);  // the scene, delta, alpha, rho_inf, peak_prominence, ...
}

// The documented default of HHT's δ is −α (eq. 15), the others' defaults are in the table.
TEST(SimulationSettings, HhtDeltaDefaultsToMinusAlpha) {
  SimulationSettings s;
  s.method.kind = MethodKind::hht;
  ASSERT_FALSE(assign_text(s, "alpha", "-0.2"));
  const Simulation sim = built(s);
  EXPECT_DOUBLE_EQ(*numeric_value(sim, "delta"), 0.2);
  EXPECT_DOUBLE_EQ(*numeric_value(sim, "beta"), 0.25 * 1.2 * 1.2);
  EXPECT_DOUBLE_EQ(*numeric_value(sim, "gamma"), 0.7);
}

TEST(SimulationSettings, TextIsParsedStrictly) {
  SimulationSettings s;
  EXPECT_EQ(assign_text(s, "courant", "0.5x")->constraint, "must be a number");
  EXPECT_EQ(assign_text(s, "courant", "")->constraint, "must be a number");
  // Issue 38: 1e400 is a number, only not a double's; the message says which.
  EXPECT_EQ(assign_text(s, "courant", "1e400")->constraint,
            "is a number beyond the range of double (magnitudes from about 2.2e-308 to 1.8e308)");
  EXPECT_EQ(assign_text(s, "courant", "1e400x")->constraint, "must be a number");
  EXPECT_EQ(assign_text(s, "elements", "2.5")->constraint, "must be an integer below 2e9");
  EXPECT_EQ(assign_text(s, "elements", "1e10")->constraint, "must be an integer below 2e9");
  EXPECT_EQ(assign_text(s, "bogus", "1")->constraint, "is not a parameter");
  EXPECT_EQ(assign_text(s, "mass", "heavy")->constraint,
            "must be one of lumped|consistent|redistributed|singular");
  ASSERT_FALSE(assign_text(s, "elements", "50"));
  EXPECT_EQ(s.scene.elements, 50);
}

// The contact keys: a law by its name, and every bad value refused by the key's name.
TEST(SimulationSettings, ContactKeysAreCheckedByName) {
  SimulationSettings s;
  ASSERT_FALSE(assign_text(s, "contact", "augmented-lagrangian"));
  ASSERT_FALSE(assign_text(s, "penalty_stiffness", "2500"));
  EXPECT_EQ(built(s).run.contact.law, ContactLaw::augmented_lagrangian);
  EXPECT_EQ(built(s).run.contact.penalty_stiffness, 2500.0);
  EXPECT_EQ(assign_text(s, "contact", "bogus")->field, "contact");
  for (const auto& [key, bad] : {std::pair{"penalty_stiffness", "0"},
                                 {"penalty_factor", "-1"},
                                 {"augmented_tolerance", "1"},
                                 {"augmented_max_iterations", "0"},
                                 {"restitution", "1.5"}}) {
    SimulationSettings t;
    ASSERT_FALSE(assign_text(t, key, bad)) << key;
    const ParameterError e = error_of(t);
    EXPECT_EQ(e.field, key);
    EXPECT_EQ(e.value, bad);
  }
}

// Paoli–Schatzman's law is central difference's (a two-step recurrence in u): the other methods
// refuse it by the key `contact`, naming the methods that take it.
TEST(SimulationSettings, AContactLawAMethodDoesNotTakeIsRefusedByName) {
  SimulationSettings s;
  ASSERT_FALSE(assign_text(s, "contact", "paoli-schatzman"));
  ASSERT_FALSE(assign_text(s, "restitution", "0.5"));
  const ParameterError e = error_of(s);  // the default method, hht
  EXPECT_EQ(e.field, "contact");
  EXPECT_EQ(e.value, "paoli-schatzman");
  EXPECT_NE(e.constraint.find("method hht does not take contact law paoli-schatzman"),
            std::string::npos)
      << e.constraint;
  EXPECT_NE(e.constraint.find("the methods that take it: cdm"), std::string::npos) << e.constraint;
  s.method.kind = MethodKind::central_difference;
  EXPECT_EQ(built(s).run.contact.law, ContactLaw::paoli_schatzman);
  EXPECT_EQ(built(s).run.contact.restitution, 0.5);
}

TEST(SimulationSettings, NanIsRejectedByName) {
  SimulationSettings s;
  ASSERT_FALSE(assign_text(s, "velocity", "nan"));
  const ParameterError e = error_of(s);
  EXPECT_EQ(e.field, "velocity");
  EXPECT_EQ(e.value, "nan");
}

TEST(SimulationSettings, ParameterTheMethodDoesNotTakeIsAnError) {
  SimulationSettings s;
  s.method.kind = MethodKind::central_difference;
  ASSERT_FALSE(assign_text(s, "delta", "0.3"));
  const ParameterError e = error_of(s);
  EXPECT_EQ(e.field, "delta");
  EXPECT_EQ(e.value, "0.3");
  EXPECT_NE(e.constraint.find("cdm"), std::string::npos);
}

// A modified mass (mass = redistributed|singular) leaves the contact DOF massless: a method whose
// descriptor does not say how it steps one is refused before the run, naming the key, its value
// and the method; central difference takes it only without stiffness-proportional damping; a
// scene of bodies does not take it yet.
TEST(SimulationSettings, ModifiedMassIsRefusedByMethodsThatDoNotStepIt) {
  SimulationSettings s;
  ASSERT_FALSE(assign_text(s, "mass", "redistributed"));
  s.method.kind = MethodKind::wilson_theta;
  ParameterError e = error_of(s);
  EXPECT_EQ(e.field, "mass");
  EXPECT_EQ(e.value, "redistributed");
  EXPECT_EQ(e.constraint.rfind("method wilson-theta does not step a mass matrix with massless "
                               "contact "
                               "DOFs (the methods that do: cdm|",
                               0),
            0u)
      << e.constraint;
  for (const MethodKind kind :
       {MethodKind::central_difference, MethodKind::hht, MethodKind::newmark,
        MethodKind::generalized_alpha, MethodKind::backward_euler}) {
    s.method.kind = kind;
    built(s);
  }
  ASSERT_FALSE(assign_text(s, "mass", "singular"));
  ASSERT_FALSE(assign_text(s, "rayleigh_stiffness", "1e-8"));
  built(s);  // HHT with stiffness damping
  s.method.kind = MethodKind::central_difference;
  e = error_of(s);
  EXPECT_EQ(e.field, "mass");
  EXPECT_EQ(e.value, "singular");
  EXPECT_EQ(e.constraint,
            "method cdm steps massless contact DOFs only without stiffness-proportional damping "
            "(rayleigh_stiffness = 1e-08)");
  SimulationSettings bodies;
  ASSERT_FALSE(assign_text(bodies, "mass", "redistributed"));
  Scene scene;
  scene.bodies = {Body{.name = "a", .velocity = 1.0, .segments = {Segment{}}},
                  Body{.name = "b", .gap = 0.1, .segments = {Segment{.elements = 1}}}};
  bodies.bodies = scene;
  e = error_of(bodies);  // a scene of bodies takes it on bodies of two elements or more
  EXPECT_EQ(e.field, "mass");
  EXPECT_EQ(e.constraint,
            "moves each contact node's mass onto its neighbour: body.b has 1 element, give it at "
            "least 2");
  bodies.bodies->bodies[1].segments[0].elements = 2;
  built(bodies);
}

TEST(SimulationSettings, NewmarkTakesDeltaOrBothBetaAndGamma) {
  SimulationSettings s;
  s.method.kind = MethodKind::newmark;
  ASSERT_FALSE(assign_text(s, "beta", "0.3"));
  EXPECT_EQ(error_of(s).field, "gamma");
  ASSERT_FALSE(assign_text(s, "gamma", "0.6"));
  const Simulation sim = built(s);
  EXPECT_DOUBLE_EQ(*numeric_value(sim, "beta"), 0.3);
  EXPECT_FALSE(numeric_value(sim, "delta").has_value());
  ASSERT_FALSE(assign_text(s, "delta", "0.1"));
  EXPECT_EQ(error_of(s).field, "delta");
}

TEST(SimulationSettings, CourantAndDtExcludeEachOther) {
  SimulationSettings s;
  ASSERT_FALSE(assign_text(s, "courant", "1"));
  EXPECT_EQ(assign_text(s, "dt", "1e-7")->field, "dt");
  SimulationSettings t;
  ASSERT_FALSE(assign_text(t, "dt", "1e-7"));
  EXPECT_EQ(assign_text(t, "courant", "1")->field, "courant");
  const Simulation sim = built(t);
  EXPECT_DOUBLE_EQ(*numeric_value(sim, "dt"), 1e-7);
}

TEST(SimulationSettings, RangesAreCheckedNotClamped) {
  SimulationSettings s;
  s.method.kind = MethodKind::hht;
  ASSERT_FALSE(assign_text(s, "alpha", "-0.7"));
  const ParameterError e = error_of(s);
  EXPECT_EQ(e.field, "alpha");
  EXPECT_EQ(e.value, "-0.7");
  EXPECT_EQ(e.constraint, "must lie in [-0.5, 0]");
}

}  // namespace
}  // namespace impactid
