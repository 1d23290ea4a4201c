// The command line as a user meets it: exit statuses, messages naming the option and value,
// JSON that carries the indicators, and `simulate` agreeing with the library.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "cli_support.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

using Output = testing::CommandOutput;

Output run(const std::string& arguments) { return testing::run_impactid(arguments); }

void expect_bad_input(const std::string& arguments, const std::string& message) {
  const Output out = run(arguments);
  EXPECT_EQ(out.status, 2) << arguments << "\n" << out.text;
  EXPECT_NE(out.text.find(message), std::string::npos) << arguments << "\n" << out.text;
}

TEST(CommandLine, BadValuesExitTwoNamingOptionAndValue) {
  expect_bad_input("simulate --elements 0", "--elements = 0: must be a positive integer");
  expect_bad_input("simulate --elements -3", "--elements = -3");
  expect_bad_input("simulate --courant 0", "--courant = 0: must be positive");
  expect_bad_input("simulate --method leapfrog", "--method = leapfrog: must be one of");
  expect_bad_input("simulate --velocity nan", "--velocity = nan: must be finite");
  expect_bad_input("simulate --density abc", "--density = abc: must be a number");
  expect_bad_input("simulate --method cdm --delta 0.3",
                   "--delta = 0.3: is not a parameter of method cdm");
  expect_bad_input("simulate --method backward-euler --alpha -0.1",
                   "--alpha = -0.1: is not a parameter of method backward-euler");
  expect_bad_input("simulate --method hht --alpha -0.7", "--alpha = -0.7: must lie in [-0.5, 0]");
  expect_bad_input("simulate --method wilson-theta --theta 1.3",
                   "--theta = 1.3: must be >= (1+sqrt(3))/2 = 1.3660254 (unconditional "
                   "stability) and finite");
  expect_bad_input("simulate --method wilson-theta --theta inf", "--theta = inf");
  expect_bad_input("simulate --method houbolt --theta 1.4",
                   "--theta = 1.4: is not a parameter of method houbolt (it applies to "
                   "wilson-theta)");
  expect_bad_input("simulate --courant 1 --dt 1e-7", "cannot be given with courant");
  expect_bad_input("simulate --history out.txt", "--history = out.txt");
  expect_bad_input("simulate --no-such-option 1", "no-such-option");
  // --set names the key as given (issue 38: `name=x: must be a number`).
  const std::string bodies = "simulate --scene " + std::string(IMPACTID_SOURCE_DIR) +
                             "/plans/two-rods.toml --set ";
  expect_bad_input(bodies + "body.striker.velocity=x",
                   "impactid simulate: --set body.striker.velocity = x: must be a number");
  expect_bad_input(bodies + "body.striker.velocity=1e400",
                   "--set body.striker.velocity = 1e400: is a number beyond the range of double");
  expect_bad_input(bodies + "name=x", "impactid simulate: --set name = x: is not a parameter");
  expect_bad_input(bodies + "velocity", "--set = velocity: must be KEY=VALUE");
}

// A word the program does not know gets the nearest it knows: a command, an option of the
// command (also in --name=value form), a top-level option. Exit status 2, as for bad input.
TEST(CommandLine, TyposGetTheNearestName) {
  expect_bad_input("simulat", "impactid: simulat is not a command; did you mean simulate?");
  expect_bad_input("expotr out.h5 --csv x",
                   "impactid: expotr is not a command; did you mean export?");
  expect_bad_input("spectra --omega-dt 1", "did you mean spectral?");
  expect_bad_input("simulate --alpah 0.1",
                   "impactid simulate: --alpah is not an option of impactid simulate; did you "
                   "mean --alpha?");
  expect_bad_input("simulate --method hht --alpah=-0.1 --elements 20", "did you mean --alpha?");
  expect_bad_input("simulate --elemnts 20", "did you mean --elements?");
  expect_bad_input("run plan.toml --thread 2",
                   "impactid run: --thread is not an option of impactid run; did you mean "
                   "--threads?");
  expect_bad_input("--verison", "impactid: --verison is not an option; did you mean --version?");
  // Nothing near: said so, without a guess.
  const Output far = run("simulate --zzzzzzzz 1");
  EXPECT_EQ(far.status, 2);
  EXPECT_NE(far.text.find("impactid simulate: --zzzzzzzz is not an option of impactid simulate."),
            std::string::npos)
      << far.text;
  EXPECT_EQ(far.text.find("did you mean"), std::string::npos) << far.text;
  // Every option known, another error: CLI11's own message.
  expect_bad_input("simulate --elements", "--elements: 1 required");
}

// `impactid` alone prints the help, as --help does, with exit status 0 (README.md, Commands).
TEST(CommandLine, BareCommandPrintsTheHelp) {
  const Output bare = run("");
  EXPECT_EQ(bare.status, 0) << bare.text;
  EXPECT_EQ(bare.text, run("--help").text);
  for (const char* command : {"simulate", "compare", "run", "export", "methods", "merge"}) {
    EXPECT_NE(bare.text.find(command), std::string::npos) << command << "\n" << bare.text;
  }
  EXPECT_EQ(bare.text.find("required"), std::string::npos) << bare.text;
}

TEST(CommandLine, HelpListsEveryOptionWithItsDefault) {
  const Output out = run("simulate --help");
  EXPECT_EQ(out.status, 0);
  for (const char* option :
       {"--length",          "--elements", "--youngs-modulus", "--density",      "--area",
        "--velocity",        "--gap",      "--mass",           "--courant",      "--dt",
        "--t-end",           "--method",   "--delta",          "--alpha",        "--beta",
        "--gamma",           "--rho-inf",  "--theta",          "--cdm-velocity", "--hht-contact",
        "--peak-prominence", "--json",     "--history"}) {
    EXPECT_NE(out.text.find(option), std::string::npos) << option;
  }
  EXPECT_NE(out.text.find("[MPa]"), std::string::npos);
  EXPECT_NE(out.text.find("default 200"), std::string::npos);
}

// `simulate --json` prints what the library computes for the same parameters.
TEST(CommandLine, JsonCarriesTheLibraryNumbers) {
  const Output out = run("simulate --method newmark --delta 0.4 --elements 40 --json");
  ASSERT_EQ(out.status, 0) << out.text;
  SimulationSettings settings;
  settings.method.kind = MethodKind::newmark;
  settings.method.given.set("delta", 0.4);
  settings.scene.elements = 40;
  SimulationWorkspace workspace;
  const Evaluation e = evaluate(std::get<Simulation>(build(settings)), workspace);
  const auto field = [&](const std::string& key) {
    const auto at = out.text.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(out.text.substr(at + key.size() + 3));
  };
  EXPECT_EQ(field("eps_p"), e.indicators.eps_p);
  EXPECT_EQ(field("eps_v"), e.indicators.eps_v);
  EXPECT_EQ(field("nop_p"), e.indicators.nop_p);
  EXPECT_EQ(field("nop_v"), e.indicators.nop_v);
  EXPECT_EQ(field("beta"), 0.25 * 1.4 * 1.4);
  EXPECT_EQ(field("gamma"), 0.9);
  EXPECT_EQ(field("steps"), static_cast<double>(derive(settings.scene).step_count));
  for (const char* key : {"\"method\":\"newmark\"", "\"status\":\"ok\"", "\"dt\":",
                          "\"contact_episodes\":", "\"energy_ratio\":", "\"wall_time_s\":",
                          "\"p_max\":"}) {
    EXPECT_NE(out.text.find(key), std::string::npos) << key;
  }
}

TEST(CommandLine, UnstableRunReportsNullIndicators) {
  const Output out = run("simulate --method cdm --courant 1.5 --json");
  ASSERT_EQ(out.status, 0) << out.text;
  EXPECT_NE(out.text.find("\"status\":\"unstable\""), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("\"eps_p\":null"), std::string::npos) << out.text;
  // The text form says there are no indicators instead of printing "nan" as if it were one.
  const Output text = run("simulate --method cdm --courant 1.5");
  ASSERT_EQ(text.status, 0) << text.text;
  EXPECT_NE(text.text.find("indicators  none: the run is unstable after"), std::string::npos)
      << text.text;
  EXPECT_EQ(text.text.find("nan"), std::string::npos) << text.text;
}

// Generalized-α's α_m and α_f follow from ρ∞ (Chung & Hulbert 1993, eq. 25):
// α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1); the JSON reports them beside β and γ.
TEST(CommandLine, JsonReportsGeneralizedAlphaWeights) {
  const Output out = run("simulate --method generalized-alpha --rho-inf 0.5 --elements 20 --json");
  ASSERT_EQ(out.status, 0) << out.text;
  const auto field = [&](const std::string& key) {
    const auto at = out.text.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return at == std::string::npos ? 0.0 : std::stod(out.text.substr(at + key.size() + 3));
  };
  EXPECT_NEAR(field("alpha_m"), 0.0, 1e-15);     // (2·0.5 − 1)/1.5
  EXPECT_NEAR(field("alpha_f"), 1.0 / 3.0, 1e-15);  // 0.5/1.5
}

TEST(CommandLine, HistoryCsvHasOneRowPerSample) {
  // In a folder that does not exist yet: it is created, as for .h5 files and results.
  const std::string folder = ::testing::TempDir() + "impactid_history_folder";
  std::filesystem::remove_all(folder);
  const std::string path = folder + "/impactid_history.csv";
  const Output out = run("simulate --method backward-euler --elements 20 --history " + path);
  ASSERT_EQ(out.status, 0) << out.text;
  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("t[s],pressure[MPa],velocity[mm/s]", 0), 0u) << header;
  long rows = 0;
  while (std::getline(in, line)) ++rows;
  SimulationSettings settings;
  settings.scene.elements = 20;
  EXPECT_EQ(rows, derive(settings.scene).step_count);
}

}  // namespace
}  // namespace impactid
