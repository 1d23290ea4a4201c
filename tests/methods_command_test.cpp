// `impactid methods` as a user drives it: every registered method with its parameters, their
// defaults (the values a run with nothing given uses) and derived coefficients, as text and JSON.
#include "study/cli/methods_command.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

#include "cli_support.hpp"
#include "core/methods/method_registry.hpp"

namespace impactid {
namespace {

using testing::run_impactid;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(MethodsCommand, ListsEveryMethodWithItsParametersAndDefaults) {
  const auto o = run_impactid("methods");
  ASSERT_EQ(o.status, 0) << o.text;
  for (const MethodDescriptor& m : method_registry()) {
    EXPECT_TRUE(contains(o.text, std::string(m.name) + "\n  " + m.summary)) << m.name;
    for (const char* name : m.parameters) {
      std::string option = name;
      std::replace(option.begin(), option.end(), '_', '-');
      EXPECT_TRUE(contains(o.text, "--" + option)) << m.name << " " << name;
    }
  }
  // HHT's δ defaults to −α; generalized-α derives α_m and α_f.
  EXPECT_TRUE(contains(o.text, "--delta          default 0.3 ")) << o.text;
  EXPECT_TRUE(contains(o.text, "derived: beta, gamma, alpha_m, alpha_f")) << o.text;
  // Houbolt (no parameter) and Wilson-θ with its θ.
  EXPECT_TRUE(contains(o.text, "houbolt\n  Houbolt (Houbolt 1950, doi:10.2514/8.1722)")) << o.text;
  EXPECT_TRUE(contains(o.text, "wilson-theta\n  Wilson-theta (Wilson, Farhoomand & Bathe 1972"))
      << o.text;
  EXPECT_TRUE(contains(o.text, "--theta          default 1.4 ")) << o.text;
  // Noh–Bathe explicit with its p, and its stability limit among the derived values.
  EXPECT_TRUE(contains(o.text, "noh-bathe\n  Noh-Bathe explicit (Noh & Bathe 2013")) << o.text;
  EXPECT_TRUE(contains(o.text, "--p              default 0.54 ")) << o.text;
  EXPECT_TRUE(contains(o.text, "derived: q0, q1, q2, omega_crit")) << o.text;
  // Kim's two-stage explicit scheme: the same key p, its own default and range, and Ω_crit.
  EXPECT_TRUE(contains(o.text, "kim-explicit\n  Kim two-stage explicit (Kim 2019, IJNME"))
      << o.text;
  EXPECT_TRUE(contains(o.text, "--p              default 0.5 ")) << o.text;
  EXPECT_TRUE(contains(o.text, "derived: omega_crit")) << o.text;
  // KR-α explicit with its rho_inf, and the scalars its matrices are built from.
  EXPECT_TRUE(contains(o.text, "kr-alpha\n  KR-alpha explicit (Kolay & Ricles 2014")) << o.text;
  EXPECT_TRUE(contains(o.text, "derived: alpha_m, alpha_f, beta, gamma")) << o.text;
}

// A user reads papers, not the project's history: every summary names its source by author and
// year or by the benchmark's equations, which the list's first line attributes; nothing refers to
// "the seed" (the benchmark paper as the project's notes called it).
TEST(MethodsCommand, SpeaksOfPapers) {
  for (const char* arguments : {"methods", "methods --json"}) {
    const auto o = run_impactid(arguments);
    ASSERT_EQ(o.status, 0) << o.text;
    std::string lower = o.text;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    EXPECT_FALSE(contains(lower, "seed")) << arguments << "\n" << o.text;
  }
  const auto o = run_impactid("methods");
  EXPECT_EQ(o.text.rfind("Each method with its paper; \"eq. N\" is an equation of Serfozo & Pere "
                         "2022, doi:10.1556/606.2022.00599.\n",
                         0),
            0u)
      << o.text;
  for (const MethodDescriptor& m : method_registry()) {
    const std::string summary = m.summary;
    EXPECT_TRUE(contains(summary, "doi:") || contains(summary, "(eq")) << m.name << ": " << summary;
  }
}

TEST(MethodsCommand, JsonGivesTheSameList) {
  const auto o = run_impactid("methods --json");
  ASSERT_EQ(o.status, 0) << o.text;
  EXPECT_EQ(o.text.front(), '[');
  for (const MethodDescriptor& m : method_registry()) {
    EXPECT_TRUE(contains(o.text, std::string("{\"name\":\"") + m.name + "\",\"label\":\"" +
                                     method_label(m) + "\",\"summary\":"))
        << m.name;
  }
  for (const char* part :
       {"{\"name\":\"alpha\",\"kind\":\"real\",\"default\":-0.3,",
        "{\"name\":\"hht_contact\",\"kind\":\"choice\",\"choices\":\"endpoint|weighted\","
        "\"default\":\"endpoint\",",
        "{\"name\":\"rho_inf\",\"kind\":\"real\",\"default\":0.8,",
        "\"derived\":[\"beta\",\"gamma\",\"alpha_m\",\"alpha_f\"]"}) {
    EXPECT_TRUE(contains(o.text, part)) << part << "\n" << o.text;
  }
  // The contact laws each takes: central difference all four, the others all but Paoli–Schatzman's.
  EXPECT_TRUE(contains(o.text,
                       "\"contact_laws\":[\"lagrange\",\"penalty\",\"augmented-lagrangian\","
                       "\"paoli-schatzman\"]"))
      << o.text;
  EXPECT_TRUE(
      contains(o.text, "\"contact_laws\":[\"lagrange\",\"penalty\",\"augmented-lagrangian\"]"))
      << o.text;
  const auto text = run_impactid("methods");
  EXPECT_TRUE(contains(text.text,
                       "  contact laws: lagrange|penalty|augmented-lagrangian|paoli-schatzman\n"))
      << text.text;
  EXPECT_EQ(run_impactid("methods --bogus").status, 2);
}

// A method's label is the head of its summary, so that its name for people is written once: what
// the figures' legends show (in their typography).
TEST(MethodsCommand, LabelIsTheSummarysHead) {
  for (const MethodDescriptor& m : method_registry()) {
    const std::string label = method_label(m);
    EXPECT_FALSE(label.empty()) << m.name;
    EXPECT_EQ(std::string(m.summary).rfind(label, 0), 0u) << m.name;
    EXPECT_FALSE(contains(label, "(") || contains(label, " with ")) << m.name << ": " << label;
  }
  const auto label_of = [](std::string_view name) {
    for (const MethodDescriptor& m : method_registry()) {
      if (name == m.name) return method_label(m);
    }
    return std::string("(not registered)");
  };
  EXPECT_EQ(label_of("cdm"), "central difference");
  EXPECT_EQ(label_of("hht"), "HHT-alpha");
  EXPECT_EQ(label_of("noh-bathe"), "Noh-Bathe explicit");
}

}  // namespace
}  // namespace impactid
