// `impactid spectral` as a user drives it: one method's spectral properties (text and --json),
// --match-damping, and bad input (exit status 2, the option named).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "core/spectral/amplification.hpp"

namespace impactid {
namespace {

struct Output {
  int status;
  std::string text;
};

Output run(const std::string& arguments) {
  const std::string command = std::string(IMPACTID_EXECUTABLE) + " " + arguments + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string text;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe.get())) text += buffer.data();
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The number after `"key":` at or after `from` in compact JSON; NaN for null or if missing.
double json_number(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\":", from);
  if (at == std::string::npos) return NAN;
  const char* start = json.c_str() + at + key.size() + 3;
  char* end = nullptr;
  const double v = std::strtod(start, &end);
  return end == start ? NAN : v;
}

TEST(SpectralCommand, JsonHasEveryField) {
  const Output o =
      run("spectral --method hht --alpha -0.3 --delta 0.45 --omega-dt 1 --omega-dt 0.1,2 --json");
  ASSERT_EQ(o.status, 0) << o.text;
  const std::string& j = o.text;
  EXPECT_EQ(j.front(), '{');
  for (const char* key :
       {"\"method\":\"hht\"", "\"parameters\":{", "\"alpha\":-0.3", "\"delta\":0.45", "\"beta\":",
        "\"gamma\":", "\"rho_inf\":", "\"period_error_coefficient\":", "\"stability\":{",
        "\"stable\":true", "\"omega_max_from\":\"default\"", "\"delta_min_period_error\":{",
        "\"eq19\":", "\"omega_dt\":[", "\"oscillatory\":true"}) {
    EXPECT_TRUE(contains(j, key)) << key << "\n" << j;
  }
  const MethodParams hht = HhtParams{.alpha = -0.3, .delta = 0.45};
  EXPECT_EQ(json_number(j, "rho_inf"), high_frequency_spectral_radius(hht));
  EXPECT_EQ(json_number(j, "period_error_coefficient"), period_error_coefficient(hht));
  // The first Omega given is reported first, with the properties at that Omega.
  const std::size_t first = j.find("\"omega_dt\":[");
  EXPECT_EQ(json_number(j, "omega_dt", first + 12), 1.0);
  EXPECT_EQ(json_number(j, "damping_ratio", first), spectral_properties(hht, 1.0).damping_ratio);
  EXPECT_EQ(json_number(j, "period_error", first), spectral_properties(hht, 1.0).period_error);
  EXPECT_NEAR(json_number(j, "limit"), 0.45, 1e-5);  // eq. 19 from the period error
  // Three Omega values: 1, then the list 0.1,2.
  std::size_t count = 0;
  for (std::size_t at = j.find("\"spectral_radius\""); at != std::string::npos;
       at = j.find("\"spectral_radius\"", at + 1)) {
    ++count;
  }
  EXPECT_EQ(count, 3u);
}

TEST(SpectralCommand, StabilityUpToTheRodsHighestMode) {
  // Central difference: unstable over the default scan, stable up to the highest mode of a
  // lumped rod at Courant 0.5 (Omega = 1), unstable at Courant 1.5 (Omega = 3).
  EXPECT_TRUE(contains(run("spectral --method cdm --json").text, "\"stable\":false"));
  const Output half = run("spectral --method cdm --courant 0.5 --json");
  EXPECT_TRUE(contains(half.text, "\"stable\":true")) << half.text;
  EXPECT_TRUE(contains(half.text, "\"omega_max\":1,")) << half.text;
  EXPECT_TRUE(contains(half.text, "\"omega_max_from\":\"courant\"")) << half.text;
  EXPECT_TRUE(contains(run("spectral --method cdm --courant 1.5 --json").text, "\"stable\":false"));
  // A consistent mass raises the highest mode by sqrt(3).
  const Output consistent = run("spectral --method cdm --courant 0.5 --mass consistent --json");
  EXPECT_NEAR(json_number(consistent.text, "omega_max"), std::sqrt(3.0), 1e-15) << consistent.text;
  const Output text = run("spectral --method newmark --delta 0.3 --omega-dt 1");
  ASSERT_EQ(text.status, 0) << text.text;
  EXPECT_TRUE(contains(text.text, "stability   max rho = ")) << text.text;
  EXPECT_TRUE(contains(text.text, ": stable")) << text.text;
}

TEST(SpectralCommand, MatchDampingFindsParametersWithThatDampingRatio) {
  const double target =
      spectral_properties(HhtParams{.alpha = -0.3, .delta = 0.45}, 1.0).damping_ratio;
  char arguments[128];
  std::snprintf(arguments, sizeof arguments, "spectral --match-damping %.17g --omega-dt 1 --json",
                target);
  const Output o = run(arguments);
  ASSERT_EQ(o.status, 0) << o.text;
  const std::string& j = o.text;
  const auto family = [&](const char* name) { return j.find(std::string("\"family\":\"") + name); };
  ASSERT_NE(family("newmark"), std::string::npos) << j;
  const double delta = json_number(j, "value", family("newmark"));
  EXPECT_NEAR(spectral_properties(NewmarkParams{.delta = delta}, 1.0).damping_ratio, target, 1e-12);
  const double alpha = json_number(j, "value", family("hht-eq19"));
  EXPECT_NEAR(alpha, -0.3, 1e-12);
  const double rho_inf = json_number(j, "value", family("generalized-alpha"));
  EXPECT_NEAR(spectral_properties(GeneralizedAlphaParams{.rho_inf = rho_inf}, 1.0).damping_ratio,
              target, 1e-12);
  // HHT with delta = -alpha cannot damp this much: reported, with what it can reach.
  const std::size_t eq15 = family("hht-eq15");
  EXPECT_TRUE(contains(j.substr(eq15, 80), "\"reachable\":false")) << j;
  EXPECT_TRUE(contains(j.substr(eq15, 400), "\"attainable\":[0,0.011")) << j;
  EXPECT_TRUE(contains(j, "\"method\":\"backward-euler\",\"damping_ratio\":")) << j;
  EXPECT_TRUE(contains(j, "\"method\":\"cdm\",\"damping_ratio\":0}")) << j;

  const Output text = run("spectral --match-damping 0.05 --omega-dt 1");
  ASSERT_EQ(text.status, 0) << text.text;
  EXPECT_TRUE(contains(text.text, "hht (delta = -alpha)       alpha     not reachable"))
      << text.text;
  EXPECT_TRUE(contains(text.text, "backward-euler")) << text.text;
}

TEST(SpectralCommand, BadInputExitsTwoNamingTheOption) {
  const struct {
    const char* arguments;
    const char* message;
  } cases[] = {
      {"spectral --omega-dt -1", "impactid spectral: --omega-dt = -1: must be positive and finite"},
      {"spectral --omega-dt x", "impactid spectral: --omega-dt = x: must be a number"},
      {"spectral --omega-dt nan",
       "impactid spectral: --omega-dt = nan: must be positive and finite"},
      {"spectral --method hht --alpha -0.7",
       "impactid spectral: --alpha = -0.7: must lie in [-0.5, 0]"},
      {"spectral --method cdm --delta 0.3",
       "impactid spectral: --delta = 0.3: is not a parameter of method cdm"},
      {"spectral --courant 0", "impactid spectral: --courant = 0:"},
      {"spectral --omega-max 0", "impactid spectral: --omega-max = 0: must be positive and finite"},
      {"spectral --courant 0.5 --omega-max 3",
       "impactid spectral: --omega-max = 3: cannot be given with --courant or --mass"},
      {"spectral --match-damping 0.1",
       "impactid spectral: --omega-dt = (missing): --match-damping needs exactly one --omega-dt"},
      {"spectral --match-damping 0.1 --omega-dt 1,2",
       "impactid spectral: --omega-dt = 2 values: --match-damping needs exactly one --omega-dt"},
      {"spectral --match-damping -0.1 --omega-dt 1",
       "impactid spectral: --match-damping = -0.1: must be >= 0 and finite"},
      {"spectral --match-damping abc --omega-dt 1",
       "impactid spectral: --match-damping = abc: must be a number"},
      {"spectral --match-damping 0.1 --omega-dt 1 --method newmark",
       "impactid spectral: --method = newmark: not used with --match-damping"},
  };
  for (const auto& c : cases) {
    const Output o = run(c.arguments);
    EXPECT_EQ(o.status, 2) << c.arguments << "\n" << o.text;
    EXPECT_TRUE(contains(o.text, c.message)) << c.arguments << "\n" << o.text;
  }
}

}  // namespace
}  // namespace impactid
