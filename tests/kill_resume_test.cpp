// Lost work and hostile files (results/README.md, "Writing: atomic replacement and
// checkpoints"): a sweep killed with SIGKILL at any moment — no handler runs, no final save —
// resumes with `impactid run --resume` to exactly the file an uninterrupted run writes, whatever
// `.tmp` the kill left behind; and a truncated or corrupt results file is refused with a
// message naming it, and never overwritten.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"
#include "study/io/results_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using testing::write_file;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("kill_resume_test", name);
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// 441 points of HHT on a 300-element rod: about 0.2 s on one core in Release with the batched
// kernel (a 100-element rod took 0.06 s, and the sweep finished before the first kill), long
// enough to land kills between checkpoints (every 0.05 s), short enough to repeat.
const char* kGridPlan = R"(
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
constexpr long kGridPoints = 21 * 21;

// `impactid run PLAN --output OUT [--resume] --threads N` in a child process, output discarded.
pid_t start_run(const fs::path& plan, const fs::path& out, bool resume, int threads) {
  const std::string thread_text = std::to_string(threads);
  const pid_t child = fork();
  if (child == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    std::vector<const char*> argv{IMPACTID_EXECUTABLE, "run",       plan.c_str(),       "--output",
                                  out.c_str(),         "--threads", thread_text.c_str()};
    if (resume) argv.push_back("--resume");
    argv.push_back(nullptr);
    execv(IMPACTID_EXECUTABLE, const_cast<char* const*>(argv.data()));
    _exit(127);
  }
  return child;
}

// The inode of a file, or 0 when it does not exist: every checkpoint renames a new file over the
// old one, so a new inode means a new checkpoint.
ino_t inode_of(const fs::path& path) {
  struct stat s {};
  return ::stat(path.c_str(), &s) == 0 ? s.st_ino : 0;
}

// Bit-identical, except that any NaN equals any NaN.
bool same_value(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Everything a study computes, equal: the grid, the status and every parameter and indicator
// value except wall_time_s (a measured time, different on every run).
void expect_same_results(const StudyResults& a, const StudyResults& b) {
  EXPECT_EQ(a.plan_text, b.plan_text);
  ASSERT_EQ(a.dimensions.size(), b.dimensions.size());
  for (std::size_t d = 0; d < a.dimensions.size(); ++d) {
    EXPECT_EQ(a.dimensions[d].name, b.dimensions[d].name);
    ASSERT_EQ(a.dimensions[d].values.size(), b.dimensions[d].values.size());
    for (std::size_t i = 0; i < a.dimensions[d].values.size(); ++i) {
      EXPECT_TRUE(same_value(a.dimensions[d].values[i], b.dimensions[d].values[i]));
    }
  }
  EXPECT_EQ(a.status, b.status);
  const auto names = [](const StudyResults& r) {
    std::vector<std::string> out;
    for (const auto* columns : {&r.parameters, &r.indicators}) {
      for (const ResultColumn& c : *columns) out.push_back(c.name);
    }
    return out;
  };
  ASSERT_EQ(names(a), names(b));
  long compared = 0;
  for (const std::string& name : names(a)) {
    if (name == "wall_time_s") continue;
    const auto& x = a.find_column(name)->values;
    const auto& y = b.find_column(name)->values;
    ASSERT_EQ(x.size(), y.size()) << name;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_TRUE(same_value(x[i], y[i])) << name << "[" << i << "]: " << x[i] << " vs " << y[i];
      ++compared;
    }
  }
  EXPECT_GT(compared, 0);
}

// How a kill is timed.
enum class KillMoment {
  at_once,            ///< right after fork(): probably before the first checkpoint
  after_delay,        ///< a seeded delay after the start
  after_checkpoint,   ///< a seeded delay after this run's first checkpoint
  during_checkpoint,  ///< as soon as a checkpoint's `.tmp` appears: in the middle of a write
};
const char* to_string(KillMoment m) {
  switch (m) {
    case KillMoment::at_once:
      return "at once";
    case KillMoment::after_delay:
      return "after a delay";
    case KillMoment::after_checkpoint:
      return "after a checkpoint";
    case KillMoment::during_checkpoint:
      return "during a checkpoint";
  }
  return "?";
}

// SIGKILL at seeded pseudo-random moments of four kinds (KillMoment), again and again, each
// time resuming with --resume (or starting afresh when no file exists yet). After each kill the
// file, if any, must be a complete results file of the plan — the atomic replacement — with no
// fewer finished points than before. The `.tmp` a kill in the middle of a write leaves is left
// for the next run to cope with; before the last run a stale `.tmp` holding garbage is planted as
// well. The last run must complete, leave no `.tmp` or any other file, and equal the
// uninterrupted run bit for bit.
TEST(KillResume, SigkillAtRandomMomentsThenResumeEqualsTheUninterruptedRun) {
  const fs::path plan = write_file(scratch("grid.toml"), kGridPlan);
  const fs::path reference_file = scratch("reference.h5");
  const fs::path folder = scratch("killed");
  fs::create_directories(folder);
  const fs::path out = folder / "grid.h5";
  fs::path temporary = out;
  temporary += ".tmp";

  const auto reference_start = Clock::now();
  const auto reference = testing::run_impactid("run " + plan.string() + " --threads 1 --output " +
                                               reference_file.string());
  const double reference_seconds = seconds_since(reference_start);
  ASSERT_EQ(reference.status, 0) << reference.text;
  const StudyResults expected = read_results(reference_file);
  ASSERT_EQ(expected.points_done(), kGridPoints);

  std::mt19937 random(20240521);  // fixed: the same schedule on every run
  // Delays are fractions of the reference time, so the schedule scales with the build (Release,
  // or several times slower under the sanitizers). The killed runs use one thread, as it did.
  const auto delay = [&] {
    const double fraction = 0.02 + 0.25 * static_cast<double>(random() % 1000) / 1000.0;
    return std::chrono::duration<double>(fraction * reference_seconds);
  };
  constexpr KillMoment kSchedule[] = {
      KillMoment::at_once,           KillMoment::after_checkpoint,  KillMoment::during_checkpoint,
      KillMoment::after_delay,       KillMoment::during_checkpoint, KillMoment::after_checkpoint,
      KillMoment::during_checkpoint, KillMoment::after_delay,       KillMoment::after_checkpoint,
      KillMoment::during_checkpoint,
  };
  long done_before = 0;
  int partial_files = 0, temporaries_left = 0;
  bool finished = false;
  for (std::size_t k = 0; k < std::size(kSchedule) && !finished; ++k) {
    const KillMoment moment = kSchedule[k];
    SCOPED_TRACE("kill " + std::to_string(k) + ", " + to_string(moment));
    const bool resume = fs::exists(out);
    const ino_t previous_checkpoint = inode_of(out);
    fs::remove(temporary);  // so that a .tmp seen below is this run's
    const Clock::time_point start = Clock::now();
    const pid_t child = start_run(plan, out, resume, 1);
    ASSERT_GT(child, 0);
    // Reaped only here or below, so the pid stays this child's (a zombie) until then.
    std::optional<int> ended;
    const auto has_ended = [&] {
      int raw = 0;
      if (!ended && waitpid(child, &raw, WNOHANG) == child) ended = raw;
      return ended.has_value();
    };
    const auto wait_for = [&](const auto& condition) {
      while (!condition() && !has_ended() && seconds_since(start) < 120) {
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
    };
    switch (moment) {
      case KillMoment::at_once:
        break;
      case KillMoment::after_delay:
        std::this_thread::sleep_for(delay());
        break;
      case KillMoment::after_checkpoint:
        wait_for([&] { return inode_of(out) != previous_checkpoint; });
        std::this_thread::sleep_for(delay());
        break;
      case KillMoment::during_checkpoint:
        wait_for([&] { return fs::exists(temporary); });
        break;
    }
    if (!has_ended()) {
      kill(child, SIGKILL);
      int raw = 0;
      ASSERT_EQ(waitpid(child, &raw, 0), child);
      ended = raw;
    }
    const double killed_after = seconds_since(start);
    if (WIFEXITED(*ended)) {
      ASSERT_EQ(WEXITSTATUS(*ended), 0) << "the run failed";
      finished = true;  // it was faster than the kill
    } else {
      ASSERT_TRUE(WIFSIGNALED(*ended) && WTERMSIG(*ended) == SIGKILL);
    }
    const bool temporary_left = fs::exists(temporary);
    temporaries_left += temporary_left;
    if (fs::exists(out)) {
      StudyResults now;
      ASSERT_NO_THROW(now = read_results(out)) << "not a complete results file";
      EXPECT_EQ(now.plan_text, kGridPlan);
      EXPECT_GE(now.points_done(), done_before) << "finished points were lost";
      done_before = now.points_done();
      if (done_before > 0 && done_before < kGridPoints) ++partial_files;
    } else {
      EXPECT_EQ(done_before, 0) << "the results file disappeared";
    }
    std::printf("kill_resume_test: kill %zu %s, after %.3f s: %ld of %ld points saved%s%s\n", k,
                to_string(moment), killed_after, done_before, kGridPoints,
                temporary_left ? ", a .tmp left" : "", finished ? " (it had finished)" : "");
  }
  std::printf("kill_resume_test: reference run %.3f s; %d kills left a partial file, %d a .tmp\n",
              reference_seconds, partial_files, temporaries_left);
  if (!finished) {
    EXPECT_GT(partial_files, 0) << "no kill landed in the middle of the sweep";
  }

  // A stale .tmp, as if the machine had died in the middle of a write.
  write_file(temporary, "stale: the head of an HDF5 file, then nothing \x89HDF\r\n");
  const std::string mode = fs::exists(out) ? " --resume" : "";
  const auto last = testing::run_impactid("run " + plan.string() + mode + " --threads 2 --output " +
                                          out.string());
  ASSERT_EQ(last.status, 0) << last.text;
  if (!mode.empty()) {
    EXPECT_NE(last.text.find(std::to_string(done_before) + " reused"), std::string::npos)
        << last.text;
  }
  EXPECT_FALSE(fs::exists(temporary)) << "a .tmp was left behind";
  std::set<std::string> left;
  for (const auto& entry : fs::directory_iterator(folder)) {
    left.insert(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::set<std::string>{"grid.h5"});
  const StudyResults resumed = read_results(out);
  EXPECT_EQ(resumed.points_done(), kGridPoints);
  expect_same_results(resumed, expected);
}

using testing::kSmallPlan;

// A results file cut short (a full disk, a copy interrupted): `run`, `run --resume` and
// `export` all refuse it with a message naming the file and the reason, and leave it as it is.
TEST(KillResume, TruncatedResultsFileIsRefusedAndLeftUntouched) {
  const fs::path plan = write_file(scratch("small.toml"), kSmallPlan);
  const fs::path out = scratch("truncated.h5");
  ASSERT_EQ(testing::run_impactid("run " + plan.string() + " --output " + out.string()).status, 0);
  const auto size = fs::file_size(out);
  ASSERT_GT(size, 1000u);
  fs::resize_file(out, size / 2);
  const std::string damaged = read_bytes(out);
  fs::path temporary = out;
  temporary += ".tmp";

  for (const std::string mode : {" --resume", ""}) {
    SCOPED_TRACE("run" + mode);
    const auto o =
        testing::run_impactid("run " + plan.string() + mode + " --output " + out.string());
    EXPECT_NE(o.status, 0) << o.text;
    EXPECT_NE(o.text.find(out.string()), std::string::npos) << o.text;
    EXPECT_NE(o.text.find("truncated"), std::string::npos) << o.text;
    EXPECT_NE(o.text.find("left untouched"), std::string::npos) << o.text;
    EXPECT_EQ(read_bytes(out), damaged) << "the damaged file was changed";
    EXPECT_FALSE(fs::exists(temporary));
  }
  const auto exported = testing::run_impactid("export " + out.string() + " --csv " +
                                              scratch("truncated_csv").string());
  EXPECT_NE(exported.status, 0) << exported.text;
  EXPECT_NE(exported.text.find(out.string()), std::string::npos) << exported.text;
  EXPECT_EQ(read_bytes(out), damaged);
}

// Other damage of the same kind: an empty file, and a file whose HDF5 signature is destroyed.
TEST(KillResume, EmptyOrCorruptResultsFileIsRefusedAndLeftUntouched) {
  const fs::path plan = write_file(scratch("small2.toml"), kSmallPlan);
  const fs::path out = scratch("corrupt.h5");
  ASSERT_EQ(testing::run_impactid("run " + plan.string() + " --output " + out.string()).status, 0);
  std::string corrupt = read_bytes(out);
  for (std::size_t i = 0; i < 64 && i < corrupt.size(); ++i) corrupt[i] = static_cast<char>(0xA5);

  for (const std::string& damaged : {std::string(), corrupt}) {
    SCOPED_TRACE(damaged.empty() ? "empty file" : "corrupt signature");
    write_file(out, damaged);
    for (const std::string mode : {" --resume", ""}) {
      const auto o =
          testing::run_impactid("run " + plan.string() + mode + " --output " + out.string());
      EXPECT_NE(o.status, 0) << o.text;
      EXPECT_NE(o.text.find(out.string()), std::string::npos) << o.text;
      EXPECT_NE(o.text.find("left untouched"), std::string::npos) << o.text;
      EXPECT_EQ(read_bytes(out), damaged) << "run" << mode << " changed the damaged file";
    }
  }
}

}  // namespace
}  // namespace impactid
