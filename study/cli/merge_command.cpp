#include "study/cli/merge_command.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/formats/utc_time.hpp"
#include "study/io/results_file.hpp"
#include "study/io/shard_merge.hpp"
#include "study/plan/plan.hpp"
#include "study/studies/practical_range.hpp"

namespace impactid {
namespace {

struct MergeArguments {
  std::vector<std::string> files;
  std::string output;
};

int merge(const MergeArguments& args) {
  const std::filesystem::path output = args.output;
  if (std::filesystem::exists(output)) {
    try {
      read_results(output);
    } catch (const std::exception& e) {
      std::cerr << "impactid merge: " << e.what() << "\nimpactid merge: " << output.string()
                << " exists but is not a readable impactid results file; it was left untouched "
                   "(remove it, or choose another --output)\n";
      return kExitFailure;
    }
  }
  std::vector<std::filesystem::path> files(args.files.begin(), args.files.end());
  MergedShards merged;
  try {
    merged = merge_shards(files);
  } catch (const MergeError& e) {
    std::cerr << "impactid merge: " << e.what() << '\n';
    return kExitBadInput;
  }
  StudyResults& results = merged.results;

  // The practical range is derived from the whole table, so the shards do not store it. The
  // plan is parsed from the text the files carry, with the plan file's folder for its scene and
  // model files, as the shards' run had it.
  remove_practical_range(results);
  Plan plan;
  try {
    plan = parse_plan(results.plan_text, merged.first.plan_file.empty()
                                             ? std::filesystem::path(results.plan_name + ".toml")
                                             : std::filesystem::path(merged.first.plan_file));
  } catch (const PlanError& e) {
    std::cerr << "impactid merge: the plan the shards carry does not load here: " << e.what()
              << '\n';
    return kExitBadInput;
  }
  std::string practical;
  if (!plan.practical.empty()) {
    const PracticalRange range = practical_range(results, plan.practical);
    store_practical_range(results, range);
    practical = "; practical range (" + range.thresholds + "): " + practical_summary(range);
  }
  results.date = utc_now();
  try {
    write_results(output, results);
  } catch (const std::exception& e) {
    std::cerr << "impactid merge: " << e.what() << '\n';
    return kExitFailure;
  }
  const long not_ok = static_cast<long>(
      std::count_if(results.status.begin(), results.status.end(), [](int s) { return s > 0; }));
  std::fprintf(stderr, "impactid merge: %s: %ld files, %ld points, %ld not ok%s; wrote %s\n",
               results.plan_name.c_str(), merged.files, results.points_total(), not_ok,
               practical.c_str(), output.string().c_str());
  return 0;
}

}  // namespace

std::function<int()> add_merge_command(CLI::App& app) {
  auto* command = app.add_subcommand(
      "merge",
      "Merge the results files of a plan's shards (impactid run --shard K/N) into the "
      "file a single run writes");
  auto args = std::make_shared<MergeArguments>();
  command->add_option("files", args->files, "The shards' results files, every shard once")
      ->required()
      ->type_name("SHARD.h5...");
  command->add_option("--output", args->output, "The merged results file")
      ->required()
      ->type_name("FILE");
  return [command, args]() -> int {
    if (!command->parsed()) return -1;
    return merge(*args);
  };
}

}  // namespace impactid
