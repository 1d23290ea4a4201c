// `impactid run` as a user drives it: a plan to a results file, --resume, Ctrl-C in the middle
// of a sweep, bad plans and unreadable result files.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "cli_support.hpp"
#include "study/io/results_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

using Output = testing::CommandOutput;

Output run(const std::string& arguments) { return testing::run_impactid(arguments); }

fs::path scratch(const std::string& name) { return testing::scratch_path("run_test", name); }

fs::path write_plan(const std::string& name, const std::string& text) {
  const fs::path path = scratch(name);
  std::ofstream(path) << text;
  return path;
}

using testing::kSmallPlan;

TEST(RunCommand, WritesResultsAndResumesWithNothingLeft) {
  const fs::path plan = write_plan("small.toml", kSmallPlan);
  const fs::path out = scratch("small.h5");
  const Output first = run("run " + plan.string() + " --threads 2 --output " + out.string());
  ASSERT_EQ(first.status, 0) << first.text;
  EXPECT_NE(first.text.find("5 computed, 0 reused"), std::string::npos) << first.text;
  const StudyResults r = read_results(out);
  EXPECT_EQ(r.points_done(), 5);
  EXPECT_EQ(r.threads, 2);
  const ResultColumn* delta = r.find_column("delta");
  ASSERT_NE(delta, nullptr);
  EXPECT_DOUBLE_EQ(delta->values[0], 0.75);  // the coupled axis at alpha = -0.5

  const Output again = run("run " + plan.string() + " --resume --output " + out.string());
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_NE(again.text.find("0 computed, 5 reused"), std::string::npos) << again.text;
}

TEST(RunCommand, DryRunCountsPointsAndRunsNothing) {
  const fs::path plan = write_plan("dry.toml", kSmallPlan);
  const fs::path out = scratch("dry.h5");
  const Output o = run("run " + plan.string() + " --dry-run --output " + out.string());
  ASSERT_EQ(o.status, 0) << o.text;
  EXPECT_NE(o.text.find("points      5"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("estimate"), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(out));
}

// --dry-run's estimate comes from a pilot: whole windows of 16 points spread over the plan, run
// by the sweep on the plan's threads, timed; the text says so. Its rate per point agrees with
// the real run's within a factor of 3 (timing one point at a time missed 4.6 times). The plan
// takes several seconds, so that the pilot (about a second at most) is a part of it on a fast,
// idle machine too (with 1681 points it sometimes ran the whole plan).
TEST(RunCommand, DryRunEstimatesFromAMeasuredPilot) {
  const fs::path plan = write_plan("pilot.toml", R"(
[scene]
elements = 400
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 80 }
delta = { from = 0.0, to = 1.0, partitions = 80 }
)");
  const fs::path out = scratch("pilot.h5");
  const Output dry =
      run("run " + plan.string() + " --dry-run --threads 1 --output " + out.string());
  ASSERT_EQ(dry.status, 0) << dry.text;
  EXPECT_FALSE(fs::exists(out));
  long pilot_points = 0, windows = 0;
  const auto at = dry.text.find("from a pilot run: ");
  ASSERT_NE(at, std::string::npos) << dry.text;
  ASSERT_EQ(
      std::sscanf(dry.text.c_str() + at, "from a pilot run: %ld of the 6561 points", &pilot_points),
      1)
      << dry.text;
  EXPECT_LT(pilot_points, 6561) << "the pilot ran the whole plan: make the plan longer";
  // Where a window of 16 points would take over a second (a slow machine, a sanitizer build),
  // the pilot times points one at a time and says so; its time is then not the sweep's.
  const std::string one_at_a_time = " spread over the plan, run one at a time in ";
  if (const auto slow = dry.text.find(one_at_a_time, at); slow != std::string::npos) {
    EXPECT_GT(std::stod(dry.text.substr(slow + one_at_a_time.size())), 0.0) << dry.text;
    return;
  }
  ASSERT_EQ(std::sscanf(dry.text.c_str() + at, "from a pilot run: %ld of the 6561 points (%ld",
                        &pilot_points, &windows),
            2)
      << dry.text;
  const std::string run_as =
      " of 16 spread over the plan) run as the sweep runs them, on 1 "
      "thread(s), in ";
  const auto in = dry.text.find(run_as, at);
  ASSERT_NE(in, std::string::npos) << dry.text;
  const double pilot_seconds = std::stod(dry.text.substr(in + run_as.size()));
  EXPECT_GE(windows, 1);
  EXPECT_GT(pilot_points, 16 * (windows - 1));
  EXPECT_LE(pilot_points, 16 * windows);
  EXPECT_GT(pilot_seconds, 0.0);

  const Output real = run("run " + plan.string() + " --threads 1 --output " + out.string());
  ASSERT_EQ(real.status, 0) << real.text;
  const auto summary = real.text.find("of 6561; ");
  ASSERT_NE(summary, std::string::npos) << real.text;
  const double real_seconds = std::stod(real.text.substr(summary + 9));
  const double ratio = (pilot_seconds / pilot_points) / (real_seconds / 6561.0);
  EXPECT_GT(ratio, 1.0 / 3.0) << dry.text << real.text;
  EXPECT_LT(ratio, 3.0) << dry.text << real.text;
}

// The summary's "not ok" counts every point of the file that is not ok, the reused ones of a
// resumed run too (it counted only the points computed in that run: 0 after a --resume).
TEST(RunCommand, SummaryCountsThePointsNotOkAlsoWhenResumed) {
  const fs::path plan = write_plan("not-ok.toml", R"(
[scene]
elements = 30
[method]
name = "cdm"
[study]
kind = "grid"
[study.axes]
courant = { values = [0.5, 1.5, 2.0] }
)");
  const fs::path out = scratch("not-ok.h5");
  const Output first = run("run " + plan.string() + " --output " + out.string());
  ASSERT_EQ(first.status, 0) << first.text;
  EXPECT_NE(first.text.find("3 computed, 0 reused, 2 not ok, of 3"), std::string::npos)
      << first.text;
  const Output again = run("run " + plan.string() + " --resume --output " + out.string());
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_NE(again.text.find("0 computed, 3 reused, 2 not ok, of 3"), std::string::npos)
      << again.text;
}

// A plan's [output] histories follow --output: results/x.h5 puts them in results/x-histories/,
// so that --output places everything the run writes (they went to the plan's folder regardless).
TEST(RunCommand, OutputPlacesTheHistoriesToo) {
  const fs::path planned = scratch("planned-histories");
  const fs::path planned_file = scratch("planned.h5");
  const fs::path plan =
      write_plan("histories.toml", std::string(testing::kSmallPlan) + "[output]\nfile = \"" +
                                       planned_file.string() + "\"\nhistories = \"" +
                                       planned.string() + "\"\n");
  // Without --output, where the plan says.
  const Output planned_run = run("run " + plan.string());
  ASSERT_EQ(planned_run.status, 0) << planned_run.text;
  EXPECT_TRUE(fs::exists(planned_file));
  EXPECT_TRUE(fs::exists(planned / "point-4.h5")) << planned_run.text;
  fs::remove_all(planned);

  const fs::path folder = scratch("elsewhere");
  const fs::path out = folder / "mine.h5";
  const Output dry = run("run " + plan.string() + " --dry-run --output " + out.string());
  ASSERT_EQ(dry.status, 0) << dry.text;
  EXPECT_NE(
      dry.text.find("histories   " + (folder / "mine-histories").string() + "/point-<index>.h5"),
      std::string::npos)
      << dry.text;
  const Output o = run("run " + plan.string() + " --output " + out.string());
  ASSERT_EQ(o.status, 0) << o.text;
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(fs::exists(folder / "mine-histories" / ("point-" + std::to_string(k) + ".h5")))
        << k << "\n"
        << o.text;
  }
  EXPECT_FALSE(fs::exists(planned)) << o.text;
}

TEST(RunCommand, BadPlanExitsTwoWithLocation) {
  const fs::path plan = write_plan("bad.toml", "[scene]\nelements = 0\n[method]\nname = \"hht\"\n"
                                               "[study]\nkind = \"grid\"\n[study.axes]\n"
                                               "alpha = { values = [-0.1] }\n");
  const Output o = run("run " + plan.string());
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find(plan.string() + ":2:"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("scene.elements = 0"), std::string::npos) << o.text;
}

TEST(RunCommand, UnreadableResultsFileIsNeverOverwritten) {
  const fs::path plan = write_plan("keep.toml", kSmallPlan);
  const fs::path out = scratch("keep.h5");
  std::ofstream(out) << "not an HDF5 file";
  const Output o = run("run " + plan.string() + " --output " + out.string());
  EXPECT_NE(o.status, 0);
  EXPECT_NE(o.text.find("left untouched"), std::string::npos) << o.text;
  std::ifstream in(out);
  std::string content((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(content, "not an HDF5 file");
}

TEST(RunCommand, ResumeRefusesAFileOfAnotherPlan) {
  const fs::path plan = write_plan("a.toml", kSmallPlan);
  const fs::path out = scratch("a.h5");
  ASSERT_EQ(run("run " + plan.string() + " --output " + out.string()).status, 0);
  const fs::path other = write_plan("b.toml", std::string(kSmallPlan) + "\n# changed\n");
  const Output o = run("run " + other.string() + " --resume --output " + out.string());
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find("different plan"), std::string::npos) << o.text;
}

// Ctrl-C in the middle of a sweep: the finished points are saved, the exit status says
// "interrupted", and --resume completes the same numbers as an uninterrupted run.
TEST(RunCommand, InterruptedSweepResumesToTheUninterruptedResult) {
  // 441 points on a 300-element rod: about 0.2 s on one thread, so that SIGINT lands after the
  // first checkpoint (0.05 s) and well before the end (the default rod's sweep takes 0.07 s).
  const std::string plan_text = R"(
[scene]
elements = 300
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 20 }
delta = { from = 0.0, to = 1.0, partitions = 20 }
[output]
checkpoint_seconds = 0.05
)";
  const fs::path plan = write_plan("long.toml", plan_text);
  const fs::path out = scratch("long.h5");

  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 2);
    execl(IMPACTID_EXECUTABLE, IMPACTID_EXECUTABLE, "run", plan.c_str(), "--threads", "1",
          "--output", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait for the first checkpoint: the handler is installed by then.
  for (int i = 0; i < 400 && !fs::exists(out); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ASSERT_TRUE(fs::exists(out)) << "no checkpoint written";
  kill(child, SIGINT);
  int raw = 0;
  waitpid(child, &raw, 0);
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 130);
  const StudyResults partial = read_results(out);
  EXPECT_GT(partial.points_done(), 0);
  EXPECT_LT(partial.points_done(), 441);

  const Output resumed = run("run " + plan.string() + " --resume --threads 2 --output " +
                             out.string());
  ASSERT_EQ(resumed.status, 0) << resumed.text;
  EXPECT_NE(resumed.text.find(std::to_string(partial.points_done()) + " reused"),
            std::string::npos)
      << resumed.text;

  const fs::path fresh = scratch("fresh.h5");
  ASSERT_EQ(run("run " + plan.string() + " --threads 2 --output " + fresh.string()).status, 0);
  const StudyResults a = read_results(out), b = read_results(fresh);
  EXPECT_EQ(a.status, b.status);
  for (const char* name : {"eps_p", "eps_v", "nop_p", "nop_v", "energy_ratio"}) {
    const auto& x = a.find_column(name)->values;
    const auto& y = b.find_column(name)->values;
    ASSERT_EQ(x.size(), y.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (std::isnan(y[i])) {
        EXPECT_TRUE(std::isnan(x[i])) << name << " " << i;
      } else {
        EXPECT_EQ(x[i], y[i]) << name << " " << i;
      }
    }
  }
}

TEST(RunCommand, ExportWritesCsv) {
  const fs::path plan = write_plan("export.toml", kSmallPlan);
  const fs::path out = scratch("export.h5");
  ASSERT_EQ(run("run " + plan.string() + " --output " + out.string()).status, 0);
  const fs::path dir = scratch("export_csv");
  const Output o = run("export " + out.string() + " --csv " + dir.string());
  ASSERT_EQ(o.status, 0) << o.text;
  std::ifstream in(dir / "points.csv");
  std::string header, line;
  std::getline(in, header);
  EXPECT_NE(header.find("eps_p"), std::string::npos) << header;
  long rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 5);
  // The far wall's indicators do not apply to this rod (NaN at every point): left out, and said.
  EXPECT_EQ(header.find("impacts"), std::string::npos) << header;
  EXPECT_NE(o.text.find("left out, NaN at every point: "), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("impacts"), std::string::npos) << o.text;
  EXPECT_NE(run("export " + scratch("missing.h5").string() + " --csv " + dir.string()).status, 0);
}

}  // namespace
}  // namespace impactid
