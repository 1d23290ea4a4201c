// Work-precision studies (`kind = "work-precision"`): plan errors name the file, the key and the
// value; the table has one point per (method, elements, courant) whatever their status; a
// point's indicators are bit-identical to `impactid simulate`; errors fall as the mesh is
// refined at a fixed Courant number. Timing values are only checked to be positive and finite.
#include "study/studies/work_precision.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_support.hpp"
#include "study/io/results_file.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

// gtest without gmock: `text` contains `part` / starts with `prefix`.
::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}
::testing::AssertionResult StartsWith(const std::string& text, const std::string& prefix) {
  if (text.rfind(prefix, 0) == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "\"" << text << "\" does not start with \"" << prefix << "\"";
}

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("impactid_work_precision_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  fs::remove_all(dir / name);
  return dir / name;
}

std::string error_of(const std::string& text) {
  try {
    parse_plan(text, "wp.toml");
  } catch (const PlanError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the plan was accepted:\n" << text;
  return "";
}

const ResultColumn& column(const StudyResults& r, const std::string& name) {
  const ResultColumn* c = r.find_column(name);
  if (!c) throw std::runtime_error("no column " + name);
  return *c;
}

// A small plan: 20-element rods at most, a few steps per run.
constexpr const char* kTinyPlan = R"(name = "tiny"
[study]
kind = "work-precision"
methods = [{ method = "cdm" }, { method = "hht", alpha = -0.3, delta = 0.45 }]
elements = [10, 20]
courant = [0.5, 2.0]
repeats = 2
)";

TEST(WorkPrecisionPlan, DefaultsAreTheRecommendedMethods) {
  const Plan plan = parse_plan("[study]\nkind = \"work-precision\"\n", "wp.toml");
  EXPECT_EQ(plan.kind, StudyKind::work_precision);
  const WorkPrecisionStudy& wp = plan.work_precision;
  ASSERT_EQ(wp.methods.size(), 5u);
  EXPECT_EQ(wp.methods[0].label, "cdm");
  EXPECT_EQ(wp.methods[2].label, "newmark delta=0.3");
  EXPECT_EQ(wp.methods[3].label, "hht alpha=-0.3 delta=0.45");
  EXPECT_EQ(wp.methods[4].label, "generalized-alpha rho_inf=0.8");
  EXPECT_EQ(wp.elements, (std::vector<long>{50, 100, 200, 400, 800}));
  EXPECT_EQ(wp.courant, (std::vector<double>{0.25, 0.5, 1.0, 2.0, 4.0}));
  EXPECT_EQ(wp.repeats, 5);
}

TEST(WorkPrecisionPlan, ErrorsNameFileKeyAndValue) {
  const std::string head = "[study]\nkind = \"work-precision\"\n";
  EXPECT_EQ(error_of(head + "courant = [0.5, -1.0]\n"),
            "wp.toml:3:17: study.courant[1] = -1.0: must be > 0");
  EXPECT_EQ(error_of(head + "courant = [0.5, 0.5]\n"),
            "wp.toml:3:17: study.courant[1] = 0.5: repeats an earlier value");
  EXPECT_EQ(error_of(head + "elements = [10, 2.5]\n"),
            "wp.toml:3:17: study.elements[1] = 2.5: must be an integer");
  EXPECT_EQ(error_of(head + "elements = [0]\n"),
            "wp.toml:3:13: study.elements[0] = 0: must be >= 1");
  EXPECT_EQ(error_of(head + "elements = 10\n"),
            "wp.toml:3:12: study.elements = 10: must be an array of element counts, e.g. "
            "[50, 100, 200]");
  EXPECT_EQ(error_of(head + "repeats = 0\n"),
            "wp.toml:3:11: study.repeats = 0: must be an integer from 1 to 100");
  EXPECT_TRUE(StartsWith(error_of(head + "methods = [{ method = \"hht\", rho_inf = 0.5 }]\n"),
                         "wp.toml:3:40: study.methods[0].rho_inf = 0.5: is not a parameter of "
                         "method hht"));
  EXPECT_TRUE(StartsWith(error_of(head + "speed = 1\n"),
                         "wp.toml:3:9: study.speed = 1: unknown key (work-precision keys: kind, "
                         "methods, elements, courant, repeats)"));
  EXPECT_EQ(error_of("[scene]\ncourant = 0.5\n" + head),
            "wp.toml:2:11: scene.courant = 0.5: is set by the work-precision study: give "
            "study.courant instead");
  EXPECT_TRUE(Contains(error_of("[method]\nname = \"hht\"\n" + head),
                       "method = { name = \"hht\" }: a work-precision study gives each method in "
                       "study.methods"));
  EXPECT_TRUE(Contains(error_of(head + "[output]\nindicators = [\"eps_p\"]\n"),
                       "output.indicators = [\"eps_p\"]: is not used by a work-precision study"));
  // A point that cannot be built on the scene is named.
  EXPECT_TRUE(
      Contains(error_of("[scene]\nt_end = 1e-7\n" + head + "elements = [10]\ncourant = [100.0]\n"),
               "(at method cdm, elements 10, courant 100)"));
}

TEST(WorkPrecisionStudy, OnePointPerMethodMeshAndCourantWhateverTheStatus) {
  const Plan plan = parse_plan(kTinyPlan, "tiny.toml");
  StudyResults r = empty_work_precision_results(plan);
  const SweepOutcome outcome = run_work_precision(plan, r, {});
  EXPECT_EQ(outcome.computed, 8);
  EXPECT_FALSE(outcome.interrupted);
  ASSERT_EQ(r.dimensions.size(), 3u);
  EXPECT_EQ(r.dimensions[0].name, "method");
  EXPECT_EQ(r.dimensions[0].values, (std::vector<double>{0, 1}));
  EXPECT_EQ(r.dimensions[1].name, "elements");
  EXPECT_EQ(r.dimensions[1].values, (std::vector<double>{10, 20}));
  EXPECT_EQ(r.dimensions[2].name, "courant");
  EXPECT_EQ(r.dimensions[2].values, (std::vector<double>{0.5, 2.0}));
  ASSERT_EQ(r.points_total(), 8);
  for (const char* name :
       {"dt", "delta", "alpha", "beta", "gamma", "eps_p", "eps_v", "nop_p", "nop_v", "p_max_ratio",
        "energy_ratio", "wall_time_s", "wall_time_max_s", "steps", "dof_steps"}) {
    EXPECT_EQ(column(r, name).values.size(), 8u) << name;
  }
  const auto& wall = column(r, "wall_time_s").values;
  const auto& wall_max = column(r, "wall_time_max_s").values;
  const auto& steps = column(r, "steps").values;
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_NE(r.status[i], kStatusNotDone) << i;
    EXPECT_TRUE(std::isfinite(wall[i]) && wall[i] > 0.0) << i;
    EXPECT_LE(wall[i], wall_max[i]) << i;
    EXPECT_GT(steps[i], 0.0) << i;
  }
  EXPECT_EQ(r.text_attributes.front(),
            (std::pair<std::string, std::string>{"method_label_0", "cdm"}));
  // HHT (method 1) is ok everywhere; its α is stored, δ as given.
  for (std::size_t i = 4; i < 8; ++i) {
    EXPECT_EQ(r.status[i], 0) << i;
    EXPECT_EQ(column(r, "alpha").values[i], -0.3);
    EXPECT_EQ(column(r, "delta").values[i], 0.45);
  }
  EXPECT_TRUE(std::isnan(column(r, "alpha").values[0]));  // cdm has no α
}

// Central difference above Courant 1 blows up: the points stay in the file, status unstable,
// with their time and steps and no error values; `impactid export` writes them too.
TEST(WorkPrecisionStudy, UnstableCentralDifferenceIsKept) {
  const fs::path plan = scratch("tiny.toml");
  std::ofstream(plan) << kTinyPlan;
  const fs::path file = scratch("tiny.h5");
  const auto run = testing::run_impactid("run " + plan.string() + " --output " + file.string());
  ASSERT_EQ(run.status, 0) << run.text;
  const StudyResults r = read_results(file);
  EXPECT_EQ(r.study_kind, "work-precision");
  ASSERT_EQ(r.points_total(), 8);
  // cdm: (10, 0.5) (10, 2) (20, 0.5) (20, 2)
  for (const std::size_t i : {std::size_t{1}, std::size_t{3}}) {
    EXPECT_EQ(r.status[i], 1) << i;
    EXPECT_TRUE(std::isnan(column(r, "eps_p").values[i]));
    EXPECT_GT(column(r, "wall_time_s").values[i], 0.0);
    EXPECT_GT(column(r, "steps").values[i], 0.0);
  }
  for (const std::size_t i : {std::size_t{0}, std::size_t{2}}) EXPECT_EQ(r.status[i], 0) << i;

  const fs::path csv = scratch("csv");
  const auto exported = testing::run_impactid("export " + file.string() + " --csv " + csv.string());
  ASSERT_EQ(exported.status, 0) << exported.text;
  std::ifstream in(csv / "points.csv");
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, 9);
}

TEST(WorkPrecisionRun, ResumeKeepsTheDonePoints) {
  const fs::path plan = scratch("resume.toml");
  std::ofstream(plan) << kTinyPlan;
  const fs::path file = scratch("resume.h5");
  ASSERT_EQ(testing::run_impactid("run " + plan.string() + " --output " + file.string()).status, 0);
  const StudyResults first = read_results(file);
  const auto again =
      testing::run_impactid("run " + plan.string() + " --resume --output " + file.string());
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_TRUE(Contains(again.text, "0 computed, 8 reused"));
  EXPECT_EQ(read_results(file).find_column("wall_time_s")->values,
            first.find_column("wall_time_s")->values);
  // Another plan's file is refused, untouched.
  std::ofstream(plan) << kTinyPlan << "# edited\n";
  EXPECT_EQ(testing::run_impactid("run " + plan.string() + " --resume --output " + file.string())
                .status,
            2);
}

double json_number(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\":");
  if (at == std::string::npos) throw std::runtime_error("no " + key + " in " + json);
  return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

TEST(WorkPrecisionStudy, IndicatorsEqualSimulateBitwise) {
  const Plan plan = parse_plan(kTinyPlan, "tiny.toml");
  StudyResults r = empty_work_precision_results(plan);
  run_work_precision(plan, r, {});
  // hht at 20 elements, Courant 0.5: flat index (1*2 + 1)*2 + 0
  const std::size_t i = 6;
  const auto sim = testing::run_impactid(
      "simulate --json --method hht --alpha -0.3 --delta 0.45 --elements 20 --courant 0.5");
  ASSERT_EQ(sim.status, 0) << sim.text;
  for (const char* key : {"eps_p", "eps_v", "nop_p", "nop_v", "p_max_ratio", "energy_ratio"}) {
    EXPECT_EQ(column(r, key).values[i], json_number(sim.text, key)) << key;
  }
  EXPECT_EQ(column(r, "dt").values[i], json_number(sim.text, "dt"));
  EXPECT_EQ(column(r, "steps").values[i], json_number(sim.text, "steps"));
}

TEST(WorkPrecisionStudy, ErrorsFallWithMeshRefinement) {
  const Plan plan = parse_plan(R"([study]
kind = "work-precision"
methods = [{ method = "backward-euler" }, { method = "hht", alpha = -0.3, delta = 0.45 }]
elements = [25, 50, 100]
courant = [1.0]
repeats = 1
)",
                               "refine.toml");
  StudyResults r = empty_work_precision_results(plan);
  run_work_precision(plan, r, {});
  for (std::size_t m = 0; m < 2; ++m) {
    for (const char* key : {"eps_p", "eps_v"}) {
      const auto& v = column(r, key).values;
      EXPECT_LT(v[3 * m + 1], v[3 * m]) << key << " method " << m;
      EXPECT_LT(v[3 * m + 2], v[3 * m + 1]) << key << " method " << m;
    }
  }
}

TEST(WorkPrecisionRun, RefusesThreads) {
  const fs::path plan = scratch("threads.toml");
  std::ofstream(plan) << kTinyPlan;
  const auto run = testing::run_impactid("run " + plan.string() + " --threads 2 --output " +
                                         scratch("threads.h5").string());
  EXPECT_EQ(run.status, 2) << run.text;
  EXPECT_TRUE(Contains(run.text,
                       "--threads 2: a work-precision study times its runs one at a "
                       "time on one thread"));
}

}  // namespace
}  // namespace impactid
