// The contact-law registry (core/contact/contact_law_registry.hpp): every law registered once
// under its name; its parameters set and read back the ContactTreatment field of their key, each
// checked by name; the traits the code outside core/contact/ reads agree with the comparisons the
// step loops make (ContactPenalties).
#include "core/contact/contact_law_registry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "core/contact/contact_treatment.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

constexpr ContactLaw kEveryLaw[] = {ContactLaw::lagrange, ContactLaw::penalty,
                                    ContactLaw::augmented_lagrangian, ContactLaw::paoli_schatzman};

TEST(ContactLawRegistry, EveryLawIsRegisteredOnceUnderItsName) {
  ASSERT_EQ(contact_law_registry().size(), std::size(kEveryLaw));
  std::set<std::string> names;
  for (const ContactLaw law : kEveryLaw) {
    const ContactLawDescriptor& d = descriptor(law);
    EXPECT_EQ(d.law, law);
    EXPECT_TRUE(names.insert(d.name).second) << d.name;
    EXPECT_EQ(find_contact_law(d.name), &d);
    EXPECT_EQ(contact_law_from_string(d.name), law);
    EXPECT_EQ(std::string(to_string(law)), d.name);
    EXPECT_FALSE(std::string(d.summary).empty()) << d.name;
  }
  EXPECT_EQ(contact_law_registry().front().law, ContactTreatment{}.law);  // the default first
  EXPECT_EQ(contact_law_names(), "lagrange|penalty|augmented-lagrangian|paoli-schatzman");
  EXPECT_EQ(find_contact_law("Penalty"), nullptr);
  EXPECT_FALSE(contact_law_from_string("springs"));
}

TEST(ContactLawRegistry, ParametersAreTakenByTheLawsThatUseThem) {
  std::string order;
  for (const ContactLawParameter& p : contact_law_parameters()) {
    order += (order.empty() ? "" : ", ") + std::string(p.name);
  }
  EXPECT_EQ(order,
            "penalty_stiffness, penalty_factor, augmented_tolerance, augmented_max_iterations, "
            "restitution");
  for (const ContactLawDescriptor& d : contact_law_registry()) {
    for (const ContactLawParameter& p : d.introduces) EXPECT_TRUE(law_takes(d, p.name)) << p.name;
    for (const char* key : d.parameters) {
      EXPECT_NE(find_contact_law_parameter(key), nullptr) << d.name << ": " << key;
    }
  }
  EXPECT_TRUE(descriptor(ContactLaw::lagrange).parameters.empty());
  EXPECT_EQ(contact_laws_taking("penalty_factor"), "penalty|augmented-lagrangian");
  EXPECT_EQ(contact_laws_taking("augmented_tolerance"), "augmented-lagrangian");
  EXPECT_EQ(contact_laws_taking("restitution"), "paoli-schatzman");
  EXPECT_EQ(find_contact_law_parameter("gap"), nullptr);
}

// Each parameter reads the default of its field, and sets and reads back the field it names.
TEST(ContactLawRegistry, ParametersSetAndReadTheirFields) {
  const ContactTreatment defaults;
  EXPECT_TRUE(std::isnan(find_contact_law_parameter("penalty_stiffness")->value(defaults)));
  EXPECT_EQ(find_contact_law_parameter("penalty_factor")->value(defaults), defaults.penalty_factor);
  EXPECT_EQ(find_contact_law_parameter("augmented_tolerance")->value(defaults),
            defaults.augmented_tolerance);
  EXPECT_EQ(find_contact_law_parameter("augmented_max_iterations")->value(defaults),
            defaults.augmented_max_iterations);
  EXPECT_TRUE(find_contact_law_parameter("augmented_max_iterations")->integer);
  ContactTreatment t;
  double v = 7.0;
  for (const ContactLawParameter& p : contact_law_parameters()) {
    p.assign(t, v);
    EXPECT_EQ(p.value(t), v) << p.name;
    v += 1.0;
  }
  EXPECT_EQ(t, (ContactTreatment{.penalty_stiffness = 7.0,
                                 .penalty_factor = 8.0,
                                 .augmented_tolerance = 9.0,
                                 .augmented_max_iterations = 10,
                                 .restitution = 11.0}));
}

// validate() is every parameter's check in the table's order, whatever the law.
TEST(ContactLawRegistry, ValidationNamesTheFirstBadParameterWhateverTheLaw) {
  for (const ContactLaw law : kEveryLaw) {
    EXPECT_FALSE(validate(ContactTreatment{.law = law})) << to_string(law);
    const ContactTreatment bad{.law = law,
                               .penalty_stiffness = -1.0,
                               .penalty_factor = 0.0,
                               .augmented_tolerance = 2.0,
                               .augmented_max_iterations = 0};
    const auto e = validate(bad);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->field, "penalty_stiffness");
    EXPECT_EQ(e->value, "-1");
    EXPECT_EQ(e->constraint, "must be a finite number > 0 [N/mm]");
  }
  for (const ContactLawParameter& p : contact_law_parameters()) {
    ContactTreatment t;
    p.assign(t, p.integer ? 0.0 : NAN);
    const auto e = p.check(t);
    ASSERT_TRUE(e) << p.name;
    EXPECT_EQ(e->field, p.name);
    EXPECT_EQ(validate(t)->field, p.name);
  }
}

// The traits the reports read (springs, explicit_force, iterates) are those the step loops test
// by comparison on the law as resolved for a system (ContactPenalties::lagrange(),
// explicit_force(); Paoli–Schatzman's resolves to Lagrange's with its restitution) and the laws'
// arithmetic (single_contact_force iterates for the augmented Lagrangian only).
TEST(ContactLawRegistry, TraitsAgreeWithTheStepLoops) {
  const SecondOrderSystem rod = testing::free_rod(4);
  for (const ContactLaw law : kEveryLaw) {
    const ContactLawDescriptor& d = descriptor(law);
    const ContactPenalties resolved =
        resolve_contact(ContactTreatment{.law = law, .restitution = 0.5}, rod);
    EXPECT_EQ(resolved.restitution, d.two_step_gap ? 0.5 : 0.0) << d.name;
    EXPECT_EQ(d.springs, !resolved.lagrange()) << d.name;
    EXPECT_EQ(d.explicit_force, resolved.explicit_force()) << d.name;
    EXPECT_EQ(d.springs, law_takes(d, "penalty_stiffness")) << d.name;
    if (!d.springs) continue;
    ContactIterations iterations;
    single_contact_force(1.0, 1.0, 0.5, ContactPenalties{.law = law, .tolerance = 1e-12},
                         iterations);
    EXPECT_EQ(d.iterates, iterations.iterations > 0) << d.name;
  }
}

}  // namespace
}  // namespace impactid
