// `impactid contact-laws` as a user drives it: every registered law with its summary and the
// parameters it takes, their defaults (those of a run with nothing given), as text and JSON; and a
// bad law's name refused with the registry's list.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "cli_support.hpp"
#include "core/contact/contact_law_registry.hpp"

namespace impactid {
namespace {

using testing::run_impactid;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(ContactLawsCommand, ListsEveryLawWithItsParametersAndDefaults) {
  const auto o = run_impactid("contact-laws");
  ASSERT_EQ(o.status, 0) << o.text;
  for (const ContactLawDescriptor& law : contact_law_registry()) {
    EXPECT_TRUE(contains(o.text, std::string(law.name) + "\n  " + law.summary)) << law.name;
    for (const char* name : law.parameters) {
      std::string option = name;
      std::replace(option.begin(), option.end(), '_', '-');
      EXPECT_TRUE(contains(o.text, "--" + option)) << law.name << " " << name;
    }
  }
  // Lagrange's law comes first and takes nothing: penalty's name follows its summary.
  EXPECT_EQ(o.text.rfind("lagrange\n  Lagrange multipliers", 0), 0u) << o.text;
  EXPECT_TRUE(contains(o.text, "lambda*g = 0\npenalty\n")) << o.text;
  EXPECT_TRUE(contains(o.text, "--penalty-stiffness          default none   [N/mm] ")) << o.text;
  EXPECT_TRUE(contains(o.text, "--augmented-tolerance        default 1e-06 ")) << o.text;
}

TEST(ContactLawsCommand, JsonGivesTheSameList) {
  const auto o = run_impactid("contact-laws --json");
  ASSERT_EQ(o.status, 0) << o.text;
  EXPECT_EQ(o.text.front(), '[');
  for (const ContactLawDescriptor& law : contact_law_registry()) {
    EXPECT_TRUE(contains(o.text, std::string("{\"name\":\"") + law.name + "\",\"summary\":"))
        << law.name;
  }
  for (const char* part :
       {"{\"name\":\"lagrange\",\"summary\":",
        "{\"name\":\"penalty_stiffness\",\"kind\":\"real\",\"unit\":\"N/mm\",\"default\":null,",
        "{\"name\":\"augmented_max_iterations\",\"kind\":\"integer\",\"unit\":\"\","
        "\"default\":100,"}) {
    EXPECT_TRUE(contains(o.text, part)) << part << "\n" << o.text;
  }
  EXPECT_EQ(run_impactid("contact-laws --bogus").status, 2);
}

TEST(ContactLawsCommand, ABadLawIsRefusedWithTheRegistrysNames) {
  const auto o = run_impactid("simulate --contact springs");
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_TRUE(contains(o.text, "--contact = springs: must be one of " + contact_law_names()))
      << o.text;
}

}  // namespace
}  // namespace impactid
