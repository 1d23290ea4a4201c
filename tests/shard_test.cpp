// Shards (study/studies/shard.hpp) and their merge (study/io/shard_merge.hpp), as a user drives
// them: `impactid run PLAN --shard K/N` (or a Slurm array task's defaults) then `impactid merge`,
// which must give the single run's file bit for bit (scripts/compare-results, h5py and numpy) and
// name whatever does not fit: a missing or duplicated shard, another plan, an unfinished shard.
#include "study/studies/shard.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "cli_support.hpp"
#include "same_run.hpp"
#include "study/io/results_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("shard_test", name);
}

testing::CommandOutput run(const std::string& arguments) {
  return testing::run_impactid(arguments);
}

// 81 HHT points (six windows of 16 and one of 1) with a practical range, so a merge has to
// compute it over the whole table; written to `file` unless --output says otherwise.
std::string grid_plan(const fs::path& file) {
  return R"(
[scene]
elements = 30
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 8 }
delta = { from = 0.0, to = 1.0, partitions = 8 }
[study.practical]
eps_p = 0.05
[output]
file = ")" +
         file.string() + "\"\n";
}
constexpr long kGridPoints = 81;

// The h5py/numpy comparison of two results files, timing left out (scripts/compare-results).
testing::CommandOutput compare(const fs::path& expected, const fs::path& actual) {
  const std::string command = "/usr/bin/python3 " IMPACTID_SOURCE_DIR "/scripts/compare-results " +
                              expected.string() + " " + actual.string() + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string text;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) text += buffer;
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

// A folder with the plan, its single run and the run of each shard of `count`, default names.
struct ShardedRun {
  fs::path plan, single;
  std::vector<fs::path> shards;
};

ShardedRun run_shards(const std::string& name, long count) {
  ShardedRun r;
  const fs::path folder = scratch(name);
  fs::create_directories(folder);
  r.plan = testing::write_file(folder / "grid.toml", grid_plan(folder / "grid.h5"));
  r.single = folder / "single.h5";
  const auto single = run("run " + r.plan.string() + " --threads 2 --output " + r.single.string());
  EXPECT_EQ(single.status, 0) << single.text;
  for (long k = 0; k < count; ++k) {
    const Shard shard{k, count};
    const auto o = run("run " + r.plan.string() + " --threads 1 --shard " + to_string(shard));
    EXPECT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find("shard " + to_string(shard)), std::string::npos) << o.text;
    r.shards.push_back(shard_file(folder / "grid.h5", shard));
    EXPECT_TRUE(fs::exists(r.shards.back())) << r.shards.back();
  }
  return r;
}

std::string join(const std::vector<fs::path>& files) {
  std::string text;
  for (const fs::path& f : files) {
    text += ' ';
    text += f.string();
  }
  return text;
}

// --- the pieces ------------------------------------------------------------------------------

TEST(Shard, ParsesKOfNAndRefusesEverythingElseNamingTheValue) {
  EXPECT_EQ(parse_shard("0/1"), (Shard{0, 1}));
  EXPECT_EQ(parse_shard("31/32"), (Shard{31, 32}));
  for (const char* bad : {"", "3", "2/2", "-1/4", "1/0", "a/4", "1/4x", "1.0/4", " 1/4"}) {
    try {
      parse_shard(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const ShardError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("--shard ") + bad), std::string::npos)
          << e.what();
    }
  }
}

TEST(Shard, SlurmArrayVariablesGiveTheTasksShard) {
  std::map<std::string, std::string> env;
  const auto lookup = [&](const char* name) -> const char* {
    const auto it = env.find(name);
    return it == env.end() ? nullptr : it->second.c_str();
  };
  EXPECT_EQ(slurm_array_shard(lookup), std::nullopt);  // not an array job
  env = {{"SLURM_ARRAY_TASK_ID", "7"},
         {"SLURM_ARRAY_TASK_MIN", "0"},
         {"SLURM_ARRAY_TASK_COUNT", "32"}};
  EXPECT_EQ(slurm_array_shard(lookup), (Shard{7, 32}));
  env = {{"SLURM_ARRAY_TASK_ID", "5"},
         {"SLURM_ARRAY_TASK_MIN", "1"},
         {"SLURM_ARRAY_TASK_COUNT", "3"},
         {"SLURM_ARRAY_TASK_STEP", "2"}};  // --array=1-5:2
  EXPECT_EQ(slurm_array_shard(lookup), (Shard{2, 3}));
  env = {{"SLURM_ARRAY_TASK_ID", "7"},
         {"SLURM_ARRAY_TASK_MIN", "1"},
         {"SLURM_ARRAY_TASK_COUNT", "3"}};  // --array=1,5,7: not evenly spaced
  EXPECT_THROW(slurm_array_shard(lookup), ShardError);
  env = {{"SLURM_ARRAY_TASK_ID", "7"}, {"SLURM_ARRAY_TASK_COUNT", "8"}};
  try {
    slurm_array_shard(lookup);
    ADD_FAILURE() << "no SLURM_ARRAY_TASK_MIN accepted";
  } catch (const ShardError& e) {
    EXPECT_NE(std::string(e.what()).find("SLURM_ARRAY_TASK_MIN"), std::string::npos) << e.what();
  }
  env = {
      {"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "8"}};
  try {
    slurm_array_shard(lookup);
    ADD_FAILURE() << "SLURM_ARRAY_TASK_ID=x accepted";
  } catch (const ShardError& e) {
    EXPECT_NE(std::string(e.what()).find("SLURM_ARRAY_TASK_ID=x"), std::string::npos) << e.what();
  }
}

// Every point in exactly one shard, whole windows interleaved, whatever the split.
TEST(Shard, ShardsCoverEveryPointOnceInInterleavedWindows) {
  for (const long total : {1L, 15L, 16L, 17L, 81L, 1000L}) {
    for (const long count : {1L, 2L, 3L, 7L, 64L}) {
      std::vector<int> seen(static_cast<std::size_t>(total), 0);
      for (long k = 0; k < count; ++k) {
        const std::vector<long> points = shard_points(total, {k, count});
        EXPECT_TRUE(std::is_sorted(points.begin(), points.end()));
        for (const long i : points) {
          ++seen[static_cast<std::size_t>(i)];
          EXPECT_EQ(shard_of_point(i, count), k);
          EXPECT_EQ(i / kShardWindow % count, k) << "not window " << i / kShardWindow << "'s shard";
        }
      }
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), total) << total << " in " << count;
    }
  }
}

TEST(Shard, DefaultFilesAreDistinctAndSortInShardOrder) {
  EXPECT_EQ(shard_file("results/grid.h5", {3, 32}), fs::path("results/grid.shard-03-of-32.h5"));
  EXPECT_EQ(shard_file("grid.h5", {0, 1}), fs::path("grid.shard-0-of-1.h5"));
  EXPECT_EQ(shard_file("a/b.h5", {9, 1000}), fs::path("a/b.shard-009-of-1000.h5"));
}

TEST(Shard, Sha256IsTheStandardOne) {
  // FIPS 180-2's examples.
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

// --- run --shard and merge ---------------------------------------------------------------------

// 1, 2 and 3 shards (3 does not divide the 6 full windows evenly with the last short one)
// merge to the single run's file: every dataset and attribute, timing aside.
TEST(ShardMerge, OneTwoOrThreeShardsMergeToTheSingleRunsFile) {
  for (const long count : {1L, 2L, 3L}) {
    SCOPED_TRACE(std::to_string(count) + " shards");
    const ShardedRun r = run_shards("split" + std::to_string(count), count);
    for (std::size_t k = 0; k < r.shards.size(); ++k) {
      const StudyResults shard = read_results(r.shards[k]);
      EXPECT_EQ(shard.points_done(),
                static_cast<long>(shard_points(kGridPoints, {static_cast<long>(k), count}).size()));
      EXPECT_EQ(shard.find_column("practical"), nullptr) << "a shard has no practical range";
    }
    const fs::path merged = r.single.parent_path() / "merged.h5";
    // Given in reverse order: the order of the files does not matter.
    std::vector<fs::path> files(r.shards.rbegin(), r.shards.rend());
    const auto o = run("merge" + join(files) + " --output " + merged.string());
    ASSERT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find(std::to_string(kGridPoints) + " points"), std::string::npos) << o.text;
    const auto same = compare(r.single, merged);
    EXPECT_EQ(same.status, 0) << same.text;
    EXPECT_NE(same.text.find("identical"), std::string::npos) << same.text;
    const StudyResults a = read_results(r.single), b = read_results(merged);
    EXPECT_EQ(b.points_done(), kGridPoints);
    EXPECT_NE(b.find_column("practical"), nullptr);
    EXPECT_EQ(a.text_attributes, b.text_attributes);  // no shard attribute left
    ASSERT_EQ(a.indicators.size(), b.indicators.size());
    EXPECT_FALSE(fs::exists(fs::path(merged.string() + ".tmp")));
  }
}

// The h5py comparison can fail: one changed value in a copy of the single run is found.
TEST(ShardMerge, TheComparisonSeesOneChangedValue) {
  const fs::path folder = scratch("compare");
  fs::create_directories(folder);
  const fs::path plan = testing::write_file(folder / "grid.toml", grid_plan(folder / "grid.h5"));
  ASSERT_EQ(run("run " + plan.string()).status, 0);
  StudyResults r = read_results(folder / "grid.h5");
  r.find_column("eps_v")->values[40] = std::nextafter(r.find_column("eps_v")->values[40], 1.0);
  write_results(folder / "changed.h5", r);
  const auto o = compare(folder / "grid.h5", folder / "changed.h5");
  EXPECT_EQ(o.status, 1) << o.text;
  EXPECT_NE(o.text.find("eps_v: 1 values differ"), std::string::npos) << o.text;
}

TEST(ShardMerge, AMissingShardIsNamed) {
  const ShardedRun r = run_shards("missing", 3);
  const fs::path merged = r.single.parent_path() / "merged.h5";
  const auto o = run("merge " + r.shards[0].string() + " " + r.shards[2].string() + " --output " +
                     merged.string());
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find("shard 1/3 is missing"), std::string::npos) << o.text;
  // Windows 1 and 4 (points 16..31 and 64..79): 32 points, the first 16.
  EXPECT_NE(o.text.find("32 points (first: 16, 17, 18, ...)"), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(merged));
}

TEST(ShardMerge, ADuplicatedShardIsNamedWithBothFiles) {
  const ShardedRun r = run_shards("duplicate", 2);
  const fs::path copy = r.single.parent_path() / "copy-of-shard-1.h5";
  fs::copy_file(r.shards[1], copy);
  const fs::path merged = r.single.parent_path() / "merged.h5";
  const auto o =
      run("merge" + join(r.shards) + " " + copy.string() + " --output " + merged.string());
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find("shard 1/2 is given twice"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find(r.shards[1].string()), std::string::npos) << o.text;
  EXPECT_NE(o.text.find(copy.string()), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(merged));
}

TEST(ShardMerge, ShardsOfAnotherPlanAreRefused) {
  const ShardedRun r = run_shards("plans", 2);
  // The same grid, one comment more: another plan text, so another hash.
  const fs::path other =
      testing::write_file(r.single.parent_path() / "other.toml",
                          grid_plan(r.single.parent_path() / "other.h5") + "# changed\n");
  ASSERT_EQ(run("run " + other.string() + " --shard 1/2").status, 0);
  const fs::path merged = r.single.parent_path() / "merged.h5";
  const auto o = run("merge " + r.shards[0].string() + " " +
                     shard_file(r.single.parent_path() / "other.h5", {1, 2}).string() +
                     " --output " + merged.string());
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find("come from different plans (plan_sha256"), std::string::npos) << o.text;
  EXPECT_FALSE(fs::exists(merged));

  // A shard whose embedded plan was edited after its run no longer matches its hash.
  StudyResults edited = read_results(r.shards[1]);
  edited.plan_text += "# edited\n";
  const fs::path edited_file = r.single.parent_path() / "edited.h5";
  write_results(edited_file, edited);
  const auto e = run("merge " + r.shards[0].string() + " " + edited_file.string() + " --output " +
                     merged.string());
  EXPECT_EQ(e.status, 2) << e.text;
  EXPECT_NE(e.text.find("is not the SHA-256 of the plan it carries"), std::string::npos) << e.text;
}

// A shard that was interrupted: merge names it and says how to finish it; --resume on that shard
// computes only its missing points; then the merge equals the single run.
TEST(ShardMerge, AnUnfinishedShardIsNamedAndResumesToTheSingleRun) {
  const ShardedRun r = run_shards("resume", 3);
  StudyResults partial = read_results(r.shards[1]);
  const std::vector<long> points = shard_points(kGridPoints, {1, 3});  // 16..31, 64..79
  for (const long i : {points[3], points[20], points[21]}) {
    partial.status[static_cast<std::size_t>(i)] = kStatusNotDone;
    for (auto* columns : {&partial.parameters, &partial.indicators}) {
      for (ResultColumn& c : *columns) c.values[static_cast<std::size_t>(i)] = std::nan("");
    }
  }
  write_results(r.shards[1], partial);
  const fs::path merged = r.single.parent_path() / "merged.h5";
  const auto refused = run("merge" + join(r.shards) + " --output " + merged.string());
  EXPECT_EQ(refused.status, 2) << refused.text;
  EXPECT_NE(refused.text.find("(shard 1/3) is not finished: 3 points (first: 19, 68, 69)"),
            std::string::npos)
      << refused.text;
  EXPECT_NE(refused.text.find("--shard 1/3 --resume"), std::string::npos) << refused.text;

  // Resuming with another shard, or without one, is refused: the file holds shard 1/3.
  for (const std::string other : {" --shard 2/3", " --shard 0/1"}) {
    const auto o =
        run("run " + r.plan.string() + other + " --resume --output " + r.shards[1].string());
    EXPECT_EQ(o.status, 2) << o.text;
    EXPECT_NE(o.text.find("holds shard 1/3"), std::string::npos) << o.text;
  }
  const auto resumed = run("run " + r.plan.string() + " --shard 1/3 --resume --threads 2");
  ASSERT_EQ(resumed.status, 0) << resumed.text;
  EXPECT_NE(resumed.text.find("3 computed, 29 reused"), std::string::npos) << resumed.text;

  const auto o = run("merge" + join(r.shards) + " --output " + merged.string());
  ASSERT_EQ(o.status, 0) << o.text;
  const auto same = compare(r.single, merged);
  EXPECT_EQ(same.status, 0) << same.text;
}

// Shard files store their datasets compressed: the other shards' points are NaN, so the file of
// one shard of eight is a fraction of the single run's; merged, the eight equal the single run.
TEST(ShardMerge, AShardsFileIsAboutTheSizeOfItsOwnPoints) {
  const fs::path folder = scratch("size");
  fs::create_directories(folder);
  const fs::path plan = testing::write_file(folder / "wide.toml", R"(
[scene]
elements = 10
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 63 }
delta = { from = 0.0, to = 1.0, partitions = 63 }
[output]
file = ")" + (folder / "wide.h5").string() + "\"\n");
  ASSERT_EQ(run("run " + plan.string() + " --output " + (folder / "single.h5").string()).status, 0);
  std::vector<fs::path> shards;
  for (long k = 0; k < 8; ++k) {
    ASSERT_EQ(run("run " + plan.string() + " --shard " + to_string(Shard{k, 8})).status, 0);
    shards.push_back(shard_file(folder / "wide.h5", {k, 8}));
  }
  const auto single_size = fs::file_size(folder / "single.h5");
  const auto shard_size = fs::file_size(shards[3]);
  std::printf("shard_test: 4096 points: single run %ju bytes, shard 3/8 %ju bytes\n",
              static_cast<std::uintmax_t>(single_size), static_cast<std::uintmax_t>(shard_size));
  EXPECT_LT(shard_size * 3, single_size);
  const fs::path merged = folder / "merged.h5";
  const auto o = run("merge" + join(shards) + " --output " + merged.string());
  ASSERT_EQ(o.status, 0) << o.text;
  const auto same = compare(folder / "single.h5", merged);
  EXPECT_EQ(same.status, 0) << same.text;
  EXPECT_GT(fs::file_size(merged) * 2, single_size)
      << "the merged file is stored as a single run's";
}

// Inside a Slurm array job, the task's shard is the default: task 5 of --array=4-6 is 1/3.
TEST(ShardMerge, ASlurmArrayTaskRunsItsShardByDefault) {
  const fs::path folder = scratch("slurm");
  fs::create_directories(folder);
  const fs::path plan = testing::write_file(folder / "grid.toml", grid_plan(folder / "grid.h5"));
  setenv("SLURM_ARRAY_TASK_ID", "5", 1);
  setenv("SLURM_ARRAY_TASK_MIN", "4", 1);
  setenv("SLURM_ARRAY_TASK_COUNT", "3", 1);
  const auto o = run("run " + plan.string());
  setenv("SLURM_ARRAY_TASK_COUNT", "two", 1);
  const auto bad = run("run " + plan.string());
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_ARRAY_TASK_MIN");
  unsetenv("SLURM_ARRAY_TASK_COUNT");
  ASSERT_EQ(o.status, 0) << o.text;
  EXPECT_NE(o.text.find("shard 1/3, from the Slurm array task"), std::string::npos) << o.text;
  EXPECT_EQ(read_results(folder / "grid.shard-1-of-3.h5").points_done(),
            static_cast<long>(shard_points(kGridPoints, {1, 3}).size()));
  EXPECT_EQ(bad.status, 2) << bad.text;
  EXPECT_NE(bad.text.find("SLURM_ARRAY_TASK_COUNT=two"), std::string::npos) << bad.text;
}

TEST(ShardMerge, BadShardsAndStudiesThatCannotBeSplitExitTwo) {
  const fs::path folder = scratch("bad");
  fs::create_directories(folder);
  const fs::path plan = testing::write_file(folder / "grid.toml", grid_plan(folder / "grid.h5"));
  const auto o = run("run " + plan.string() + " --shard 3/3");
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_NE(o.text.find("--shard 3/3: K must lie in 0..2"), std::string::npos) << o.text;

  const fs::path optimize = testing::write_file(folder / "opt.toml", R"(
[scene]
elements = 30
[method]
name = "hht"
[study]
kind = "optimize"
algorithm = "COBYLA"
objective = "eps_p"
max_evaluations = 5
[study.parameters]
alpha = { from = -0.5, to = 0.0 }
)");
  const auto opt = run("run " + optimize.string() + " --shard 0/2");
  EXPECT_EQ(opt.status, 2) << opt.text;
  EXPECT_NE(opt.text.find("only grid and list studies are split in shards"), std::string::npos)
      << opt.text;

  const auto merge_missing =
      run("merge " + (folder / "nothing.h5").string() + " --output " + (folder / "m.h5").string());
  EXPECT_EQ(merge_missing.status, 2) << merge_missing.text;
  EXPECT_NE(merge_missing.text.find((folder / "nothing.h5").string()), std::string::npos)
      << merge_missing.text;
}

}  // namespace
}  // namespace impactid
