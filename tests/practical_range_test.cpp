// The practical range: which points pass the plan's thresholds and how far they extend, on
// hand-made tables whose answer is known; then `impactid run` storing it in a results file and
// recomputing it on --resume.
#include "study/studies/practical_range.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

#include "cli_support.hpp"
#include "study/io/results_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ResultColumn column(const std::string& name, std::vector<double> values) {
  return {name, "1", name, "", std::move(values)};
}

// A one-dimensional grid over delta with eps_p and nop_p per point.
StudyResults table_1d(std::vector<double> delta, std::vector<int> status, std::vector<double> eps,
                      std::vector<double> nop) {
  StudyResults r;
  r.dimensions.push_back({"delta", "1", std::move(delta)});
  r.status = std::move(status);
  r.indicators.push_back(column("eps_p", std::move(eps)));
  r.indicators.push_back(column("nop_p", std::move(nop)));
  return r;
}

const std::vector<IndicatorConstraint> kThresholds{{"eps_p", std::nullopt, 0.03},
                                                   {"nop_p", std::nullopt, 15.0}};

void expect_mask(const PracticalRange& range, const std::vector<double>& expected) {
  ASSERT_EQ(range.mask.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::isnan(expected[i])) {
      EXPECT_TRUE(std::isnan(range.mask[i])) << "point " << i;
    } else {
      EXPECT_EQ(range.mask[i], expected[i]) << "point " << i;
    }
  }
}

TEST(PracticalRange, OneDimensionalContiguous) {
  // Like Fig. 3: too many peaks at small delta, too large an error at the far end.
  const StudyResults r = table_1d({0.0, 0.25, 0.5, 0.75, 1.0}, {0, 0, 0, 0, 0},
                                  {0.02, 0.02, 0.025, 0.03, 0.031}, {40, 15, 9, 5, 5});
  const PracticalRange range = practical_range(r, kThresholds);
  expect_mask(range, {0, 1, 1, 1, 0});  // the bounds are inclusive: 15 peaks, eps_p = 0.03
  EXPECT_EQ(range.points, 3);
  EXPECT_EQ(range.points_done, 5);
  EXPECT_EQ(range.points_total, 5);
  EXPECT_TRUE(range.one_dimensional);
  EXPECT_TRUE(range.contiguous());
  ASSERT_EQ(range.intervals.size(), 1u);
  EXPECT_EQ(range.intervals[0].first, 1);
  EXPECT_EQ(range.intervals[0].last, 3);
  EXPECT_EQ(range.intervals[0].from, 0.25);
  EXPECT_EQ(range.intervals[0].to, 0.75);
  ASSERT_EQ(range.extents.size(), 1u);
  EXPECT_EQ(range.extents[0].name, "delta");
  EXPECT_TRUE(range.extents[0].is_dimension);
  EXPECT_EQ(range.extents[0].min, 0.25);
  EXPECT_EQ(range.extents[0].max, 0.75);
  EXPECT_EQ(range.thresholds, "eps_p <= 0.03, nop_p <= 15");
  EXPECT_EQ(intervals_text(range), "[0.25, 0.75]");
  EXPECT_EQ(practical_summary(range), "delta in [0.25, 0.75] (3 of 5 points)");
}

TEST(PracticalRange, OneDimensionalSplitIntoTwoIntervals) {
  // Peaks counts that are not monotone (as Newmark's below delta = 0.2) split the range.
  const StudyResults r = table_1d({0.1, 0.2, 0.3, 0.4, 0.5, 0.6}, {0, 0, 0, 0, 0, 0},
                                  {0.01, 0.01, 0.01, 0.01, 0.01, 0.01}, {10, 12, 30, 14, 13, 12});
  const PracticalRange range = practical_range(r, kThresholds);
  expect_mask(range, {1, 1, 0, 1, 1, 1});
  EXPECT_EQ(range.points, 5);
  EXPECT_FALSE(range.contiguous());
  ASSERT_EQ(range.intervals.size(), 2u);
  EXPECT_EQ(range.intervals[0].first, 0);
  EXPECT_EQ(range.intervals[0].last, 1);
  EXPECT_EQ(range.intervals[1].first, 3);
  EXPECT_EQ(range.intervals[1].last, 5);
  EXPECT_EQ(intervals_text(range), "[0.1, 0.2] [0.4, 0.6]");
  // The extent spans both intervals.
  EXPECT_EQ(range.extents[0].min, 0.1);
  EXPECT_EQ(range.extents[0].max, 0.6);
  EXPECT_EQ(practical_summary(range), "delta in [0.1, 0.2] [0.4, 0.6] (5 of 6 points)");
}

TEST(PracticalRange, PointsThatAreNotOkAreNeverPractical) {
  // Indicators of an unstable or failed run are NaN in a real table; finite values here make
  // sure the status alone excludes the point.
  const StudyResults r = table_1d({0.0, 0.5, 1.0}, {1, 0, 2}, {0.01, 0.01, 0.01}, {1, 1, 1});
  const PracticalRange range = practical_range(r, kThresholds);
  expect_mask(range, {0, 1, 0});
  EXPECT_EQ(range.points, 1);
  EXPECT_EQ(range.points_done, 3);
  ASSERT_EQ(range.intervals.size(), 1u);
  EXPECT_EQ(range.intervals[0].from, 0.5);
  EXPECT_EQ(range.intervals[0].to, 0.5);
}

TEST(PracticalRange, NotDonePointsAreUnknownAndBreakIntervals) {
  const StudyResults r = table_1d({0.0, 0.25, 0.5, 0.75, 1.0}, {0, 0, -1, 0, 0},
                                  {0.01, 0.01, kNaN, 0.01, 0.01}, {5, 5, kNaN, 5, 5});
  const PracticalRange range = practical_range(r, kThresholds);
  expect_mask(range, {1, 1, kNaN, 1, 1});
  EXPECT_EQ(range.points, 4);
  EXPECT_EQ(range.points_done, 4);
  ASSERT_EQ(range.intervals.size(), 2u);  // nothing is claimed about the point not yet run
  EXPECT_EQ(intervals_text(range), "[0, 0.25] [0.75, 1]");
  EXPECT_EQ(practical_summary(range), "delta in [0, 0.25] [0.75, 1] (4 of 5 points (1 not done))");
}

TEST(PracticalRange, NanIndicatorOfAnOkPointFailsItsThreshold) {
  const StudyResults r = table_1d({0.0, 1.0}, {0, 0}, {kNaN, 0.01}, {5, 5});
  expect_mask(practical_range(r, kThresholds), {0, 1});
}

TEST(PracticalRange, DescendingAxisGivesOrderedIntervals) {
  const StudyResults r = table_1d({1.0, 0.5, 0.0}, {0, 0, 0}, {0.01, 0.01, 0.5}, {5, 5, 5});
  const PracticalRange range = practical_range(r, kThresholds);
  ASSERT_EQ(range.intervals.size(), 1u);
  EXPECT_EQ(range.intervals[0].from, 0.5);
  EXPECT_EQ(range.intervals[0].to, 1.0);
}

TEST(PracticalRange, LowerBoundsAndTheirText) {
  const StudyResults r = table_1d({0.0, 0.5, 1.0}, {0, 0, 0}, {0.01, 0.02, 0.03}, {5, 5, 5});
  const std::vector<IndicatorConstraint> t{{"eps_p", 0.015, 0.025}, {"nop_p", 1.0, std::nullopt}};
  EXPECT_EQ(thresholds_text(t), "0.015 <= eps_p <= 0.025, nop_p >= 1");
  expect_mask(practical_range(r, t), {0, 1, 0});
}

TEST(PracticalRange, ThresholdOnAnIndicatorTheTableLacksMatchesNothing) {
  const StudyResults r = table_1d({0.0, 1.0}, {0, 0}, {0.01, 0.01}, {5, 5});
  const PracticalRange range = practical_range(r, {{{"p_max", std::nullopt, 10.0}}});
  EXPECT_EQ(range.points, 0);
  EXPECT_TRUE(range.intervals.empty());
  EXPECT_TRUE(std::isnan(range.extents[0].min));
  EXPECT_EQ(practical_summary(range), "no practical point (0 of 2 points)");
}

// A 3 x 4 grid alpha x delta, delta fastest, with a coupled column beta; practical where
// delta >= -alpha + 0.25 (a diagonal boundary), except one unstable point.
TEST(PracticalRange, TwoDimensionalExtentsAlongEveryAxisAndColumn) {
  StudyResults r;
  r.dimensions.push_back({"alpha", "1", {-0.5, -0.25, 0.0}});
  r.dimensions.push_back({"delta", "1", {0.0, 0.25, 0.5, 0.75}});
  std::vector<double> eps, nop, beta;
  for (const double alpha : r.dimensions[0].values) {
    for (const double delta : r.dimensions[1].values) {
      const bool good = delta >= -alpha + 0.25;
      r.status.push_back(alpha == 0.0 && delta == 0.75 ? 1 : 0);  // one unstable point
      eps.push_back(good ? 0.01 : 0.1);
      nop.push_back(5);
      beta.push_back(0.25 * (1 + delta) * (1 + delta));
    }
  }
  r.parameters.push_back(column("beta", beta));
  r.indicators.push_back(column("eps_p", eps));
  r.indicators.push_back(column("nop_p", nop));

  const PracticalRange range = practical_range(r, kThresholds);
  // alpha = -0.5: delta = 0.75; alpha = -0.25: delta 0.5, 0.75; alpha = 0: 0.25, 0.5 (0.75 is
  // unstable).
  expect_mask(range, {0, 0, 0, 1, 0, 0, 1, 1, 0, 1, 1, 0});
  EXPECT_EQ(range.points, 5);
  EXPECT_FALSE(range.one_dimensional);
  EXPECT_FALSE(range.contiguous());
  EXPECT_TRUE(range.intervals.empty());
  ASSERT_EQ(range.extents.size(), 3u);
  EXPECT_EQ(range.extents[0].name, "alpha");
  EXPECT_EQ(range.extents[0].min, -0.5);
  EXPECT_EQ(range.extents[0].max, 0.0);
  EXPECT_EQ(range.extents[1].name, "delta");
  EXPECT_EQ(range.extents[1].min, 0.25);
  EXPECT_EQ(range.extents[1].max, 0.75);
  EXPECT_EQ(range.extents[2].name, "beta");
  EXPECT_FALSE(range.extents[2].is_dimension);
  EXPECT_EQ(range.extents[2].min, 0.25 * 1.25 * 1.25);
  EXPECT_EQ(range.extents[2].max, 0.25 * 1.75 * 1.75);
  EXPECT_EQ(practical_summary(range),
            "5 of 12 points: alpha in [-0.5, 0], delta in [0.25, 0.75]; beta in [0.390625, "
            "0.765625]");
}

TEST(PracticalRange, StoredAsAColumnAndAttributesThatSurviveTheFile) {
  StudyResults r = table_1d({0.0, 0.5, 1.0}, {0, 0, -1}, {0.05, 0.01, kNaN}, {5, 5, kNaN});
  r.plan_name = "p";
  r.study_kind = "grid";
  r.method = "newmark";
  r.parameters.push_back(column("gamma", {0.5, 1.0, kNaN}));
  const PracticalRange range = practical_range(r, kThresholds);
  store_practical_range(r, range);
  store_practical_range(r, range);  // replaces, never duplicates
  ASSERT_EQ(r.indicators.size(), 3u);
  EXPECT_EQ(r.indicators.back().name, "practical");
  EXPECT_EQ(r.indicators.back().definition, "eps_p <= 0.03, nop_p <= 15");

  const fs::path path =
      fs::path(::testing::TempDir()) / ("practical_range_test_" + std::to_string(getpid()) + ".h5");
  write_results(path, r);
  const StudyResults back = read_results(path);
  fs::remove(path);
  const ResultColumn* practical = back.find_column("practical");
  ASSERT_NE(practical, nullptr);
  EXPECT_EQ(practical->units, "1");
  EXPECT_EQ(practical->values[0], 0.0);
  EXPECT_EQ(practical->values[1], 1.0);
  EXPECT_TRUE(std::isnan(practical->values[2]));
  const auto numeric = [&](const std::string& name) {
    for (const auto& [n, v] : back.numeric_attributes) {
      if (n == name) return v;
    }
    ADD_FAILURE() << "no attribute " << name;
    return kNaN;
  };
  const auto text = [&](const std::string& name) {
    for (const auto& [n, v] : back.text_attributes) {
      if (n == name) return v;
    }
    ADD_FAILURE() << "no attribute " << name;
    return std::string();
  };
  EXPECT_EQ(numeric("practical_points"), 1.0);
  EXPECT_EQ(numeric("practical_delta_min"), 0.5);
  EXPECT_EQ(numeric("practical_delta_max"), 0.5);
  EXPECT_EQ(numeric("practical_gamma_min"), 1.0);
  EXPECT_EQ(numeric("practical_gamma_max"), 1.0);
  EXPECT_EQ(text("practical_thresholds"), "eps_p <= 0.03, nop_p <= 15");
  EXPECT_EQ(text("practical_intervals"), "[0.5, 0.5]");

  StudyResults stripped = back;
  remove_practical_range(stripped);
  EXPECT_EQ(stripped.find_column("practical"), nullptr);
  EXPECT_TRUE(stripped.numeric_attributes.empty());
  EXPECT_TRUE(stripped.text_attributes.empty());
  EXPECT_EQ(stripped.indicators.size(), 2u);
}

// ---- end to end: `impactid run` -----------------------------------------------------------

using Output = testing::CommandOutput;

Output run(const std::string& arguments) { return testing::run_impactid(arguments); }

fs::path scratch(const std::string& name) {
  return testing::scratch_path("practical_test", name);
}

// Newmark over delta on a coarse rod: delta = 0 chatters (unstable), small delta rings (many
// peaks) and the error grows with delta, so the practical points are a strict subset.
const char* kPlan = R"(
[scene]
elements = 30
[method]
name = "newmark"
[study]
kind = "grid"
[study.axes]
delta = { from = 0.0, to = 1.0, partitions = 10 }
[study.practical]
eps_p = 0.08
nop_p = { max = 10 }
)";

double attribute(const StudyResults& r, const std::string& name) {
  for (const auto& [n, v] : r.numeric_attributes) {
    if (n == name) return v;
  }
  ADD_FAILURE() << "no numeric attribute " << name;
  return kNaN;
}

std::string text_attribute(const StudyResults& r, const std::string& name) {
  for (const auto& [n, v] : r.text_attributes) {
    if (n == name) return v;
  }
  ADD_FAILURE() << "no text attribute " << name;
  return "";
}

// The stored range must be what practical_range() gives on the stored indicators.
void expect_consistent(const StudyResults& stored) {
  StudyResults table = stored;
  remove_practical_range(table);
  const PracticalRange range =
      practical_range(table, {{{"eps_p", std::nullopt, 0.08}, {"nop_p", std::nullopt, 10.0}}});
  const ResultColumn* practical = stored.find_column("practical");
  ASSERT_NE(practical, nullptr);
  ASSERT_EQ(practical->values.size(), range.mask.size());
  for (std::size_t i = 0; i < range.mask.size(); ++i) {
    EXPECT_EQ(practical->values[i], range.mask[i]) << i;
  }
  EXPECT_EQ(attribute(stored, "practical_points"), static_cast<double>(range.points));
  EXPECT_EQ(attribute(stored, "practical_delta_min"), range.extents[0].min);
  EXPECT_EQ(attribute(stored, "practical_delta_max"), range.extents[0].max);
  EXPECT_EQ(text_attribute(stored, "practical_intervals"), intervals_text(range));
  EXPECT_EQ(text_attribute(stored, "practical_thresholds"), "eps_p <= 0.08, nop_p <= 10");
}

TEST(PracticalRangeRun, StoredInTheResultsFileAndRecomputedOnResume) {
  const fs::path plan = scratch("practical.toml");
  std::ofstream(plan) << kPlan;
  const fs::path out = scratch("practical.h5");
  const Output first = run("run " + plan.string() + " --output " + out.string());
  ASSERT_EQ(first.status, 0) << first.text;
  EXPECT_NE(first.text.find("practical range (eps_p <= 0.08, nop_p <= 10): delta in ["),
            std::string::npos)
      << first.text;
  const StudyResults r = read_results(out);
  expect_consistent(r);
  const double points = attribute(r, "practical_points");
  EXPECT_GT(points, 0.0);  // the thresholds separate the grid: neither none nor all
  EXPECT_LT(points, 11.0);
  // Measured on this rod: 13 peaks at delta = 0.4, 9 at 0.5; eps_p = 0.076 at delta = 1.
  EXPECT_EQ(attribute(r, "practical_delta_min"), 0.5);
  EXPECT_EQ(attribute(r, "practical_delta_max"), 1.0);
  EXPECT_EQ(text_attribute(r, "practical_intervals"), "[0.5, 1]");
  EXPECT_FALSE(std::isnan(attribute(r, "practical_beta_min")));  // parameter columns too
  // The column is an indicator with its thresholds as its definition.
  const ResultColumn& last = r.indicators.back();
  EXPECT_EQ(last.name, "practical");
  EXPECT_EQ(last.definition, "eps_p <= 0.08, nop_p <= 10");

  // Resume with nothing left: the range is dropped and recomputed, not duplicated.
  const Output again = run("run " + plan.string() + " --resume --output " + out.string());
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_NE(again.text.find("0 computed, 11 reused"), std::string::npos) << again.text;
  expect_consistent(read_results(out));

  // Resume a file with points missing (as a checkpoint has them) but a practical column
  // from an earlier save: the sweep fills the points, the range follows them.
  StudyResults partial = read_results(out);
  for (const std::size_t i : {2u, 7u}) {
    partial.status[i] = kStatusNotDone;
    for (auto* columns : {&partial.parameters, &partial.indicators}) {
      for (ResultColumn& c : *columns) c.values[i] = kNaN;
    }
  }
  write_results(out, partial);
  const Output resumed = run("run " + plan.string() + " --resume --output " + out.string());
  ASSERT_EQ(resumed.status, 0) << resumed.text;
  EXPECT_NE(resumed.text.find("2 computed, 9 reused"), std::string::npos) << resumed.text;
  const StudyResults final_table = read_results(out);
  expect_consistent(final_table);
  EXPECT_EQ(attribute(final_table, "practical_points"), points);
}

TEST(PracticalRangeRun, ListStudyAndDryRun) {
  const fs::path plan = scratch("list.toml");
  std::ofstream(plan) << R"(
[scene]
elements = 30
[study]
kind = "list"
points = [{ method = "backward-euler" }, { method = "newmark", delta = 0.0 }, { method = "cdm" }]
[study.practical]
nop_p = 1000
)";
  const fs::path out = scratch("list.h5");
  const Output dry = run("run " + plan.string() + " --dry-run --output " + out.string());
  ASSERT_EQ(dry.status, 0) << dry.text;
  EXPECT_NE(dry.text.find("practical   nop_p <= 1000"), std::string::npos) << dry.text;
  const Output o = run("run " + plan.string() + " --output " + out.string());
  ASSERT_EQ(o.status, 0) << o.text;
  const StudyResults r = read_results(out);
  const ResultColumn* practical = r.find_column("practical");
  ASSERT_NE(practical, nullptr);
  // Newmark with delta = 0 chatters on the wall and is reported unstable: not practical.
  EXPECT_EQ(r.status[1], 1);
  EXPECT_EQ(practical->values, (std::vector<double>{1.0, 0.0, 1.0}));
  EXPECT_EQ(text_attribute(r, "practical_intervals"), "[0, 0] [2, 2]");
  EXPECT_EQ(attribute(r, "practical_point_min"), 0.0);
  EXPECT_EQ(attribute(r, "practical_point_max"), 2.0);
}

}  // namespace
}  // namespace impactid
