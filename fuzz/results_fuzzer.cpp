// libFuzzer target: a valid results file with the input's bytes applied to it as byte flips,
// then read by every reader of results files (study/io/results_file.hpp, issue 38, item 5).
//
// At start the fuzzer writes its two base files (fuzz/results_input.hpp: kBasePlan run with the
// sweep, written as `impactid run` and `impactid run --shard` write it) into a private temporary
// folder; each input is flips applied to one of them (results_input.hpp describes the input).
// The bases are made by the program under test, so they follow its layout (a later writer's
// checksums, say) without a binary file in the repository.
//
// The contract under test: each reader either succeeds or throws its documented error —
//   - read_results: Hdf5Error (run --resume, export and merge start with it);
//   - export_csv of a table read_results returned: std::runtime_error naming the folder;
//   - shard_mark (run --resume and merge): ShardError;
//   - `impactid merge` of the file alone: merge_shards throws MergeError, never Hdf5Error; then
//     the practical range of the plan the file carries (a PlanError if it does not parse) and
//     the merged file's write (Hdf5Error);
//   - the resume path of `impactid run` (study/cli/run_command.cpp): when the file's plan text
//     and points are the plan's, the sweep is run over the table read (it computes the points
//     the file has not done, each a few microseconds here), the practical range and the verdicts
//     are summed up and the table is written again: no exception at all but Hdf5Error from that
//     write;
//   - is_spectral_results_file and is_history_file (the overwrite guards): never throw.
// A crash, a sanitizer report, a hang, an out-of-memory or an exception of another type is a
// finding. Run it with scripts/fuzz; seeds fuzz/corpus/results/.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <typeinfo>
#include <vector>

#include "fuzz/results_input.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/io/history_file.hpp"
#include "study/io/results_file.hpp"
#include "study/io/shard_merge.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/practical_range.hpp"
#include "study/studies/shard.hpp"
#include "study/studies/spectral_study.hpp"
#include "study/studies/sweep.hpp"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "results_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

struct Fixture {
  fs::path folder;
  impactid::Plan plan;
  std::vector<std::string> bases;  // the files' bytes

  Fixture() {
    std::string pattern = (fs::temp_directory_path() / "impactid-results-fuzzer-XXXXXX").string();
    if (!mkdtemp(pattern.data())) finding("cannot create a temporary folder");
    folder = pattern;
    plan = impactid::parse_plan(impactid::fuzzing::kBasePlan, folder / "fuzz.toml");
    bases = impactid::fuzzing::write_bases(plan, folder);
    for (std::size_t k = 0; k < bases.size(); ++k) {
      if (bases[k].empty()) finding("cannot read back base-" + std::to_string(k) + ".h5");
    }
    // IMPACTID_RESULTS_FUZZER_BASES=DIR keeps a copy of the bases (to place seeds' flips).
    if (const char* keep = std::getenv("IMPACTID_RESULTS_FUZZER_BASES")) {
      for (const char* name : {"base-0.h5", "base-1.h5"}) {
        fs::copy_file(folder / name, fs::path(keep) / name, fs::copy_options::overwrite_existing);
      }
    }
  }
  ~Fixture() {
    std::error_code ec;
    fs::remove_all(folder, ec);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// The base with the input applied (results_input.hpp).
std::string mutated(const std::uint8_t* data, std::size_t size) {
  return impactid::fuzzing::apply_input(fixture().bases, data, size);
}

// `impactid run --resume`'s use of a file it read: the checks of run_command.cpp, then the sweep
// over the table and the final save.
void resume(impactid::StudyResults results, const fs::path& output) {
  const impactid::Plan& plan = fixture().plan;
  if (results.plan_text != plan.text) return;  // "written by a different plan"
  const impactid::PointSet points(plan);
  bool same = results.dimensions.size() == points.dimension_names().size();
  for (std::size_t d = 0; same && d < results.dimensions.size(); ++d) {
    same = results.dimensions[d].name == points.dimension_names()[d] &&
           results.dimensions[d].values == points.dimension_values()[d] &&
           results.dimensions[d].labels == points.dimension_labels()[d];
  }
  if (!same) return;  // "the points differ from those of the plan"
  try {
    if (impactid::shard_mark(results)) return;  // base 1: "holds shard 0/1, not the whole plan"
  } catch (const impactid::ShardError&) {
    return;
  }
  impactid::remove_practical_range(results);
  std::vector<long> all(static_cast<std::size_t>(points.size()));
  std::iota(all.begin(), all.end(), 0L);
  impactid::run_sweep(points, all, results, impactid::SweepOptions{});
  impactid::store_practical_range(results, impactid::practical_range(results, plan.practical));
  static_cast<void>(impactid::verdict_summary(results));
  try {
    impactid::write_results(output, results);
  } catch (const impactid::Hdf5Error&) {
  }
}

// `impactid merge FILE --output MERGED` (study/cli/merge_command.cpp): the merge, the practical
// range of the plan the file carries, the write.
void merge(const fs::path& file, const fs::path& output) {
  impactid::MergedShards merged;
  try {
    merged = impactid::merge_shards({file});
  } catch (const impactid::MergeError&) {
    return;
  }
  impactid::StudyResults& results = merged.results;
  impactid::remove_practical_range(results);
  impactid::Plan plan;
  try {
    plan = impactid::parse_plan(results.plan_text, fixture().folder / "fuzz.toml");
  } catch (const impactid::PlanError&) {
    return;
  }
  if (!plan.practical.empty()) {
    impactid::store_practical_range(results, impactid::practical_range(results, plan.practical));
  }
  try {
    impactid::write_results(output, results);
  } catch (const impactid::Hdf5Error&) {
  }
}

void read_every_way(const fs::path& file) {
  const fs::path folder = fixture().folder;
  // The overwrite guards of run, simulate and spectral: never throw.
  static_cast<void>(impactid::is_spectral_results_file(file));
  static_cast<void>(impactid::is_history_file(file));
  merge(file, folder / "merged.h5");
  impactid::StudyResults results;
  try {
    results = impactid::read_results(file);
  } catch (const impactid::Hdf5Error& e) {
    if (std::string(e.what()).rfind(file.string(), 0) != 0) {
      finding(std::string("an Hdf5Error that does not name the file: ") + e.what());
    }
    return;
  }
  try {
    static_cast<void>(impactid::shard_mark(results));
  } catch (const impactid::ShardError&) {
  }
  const fs::path csv = folder / "csv";
  try {
    impactid::export_csv(results, csv);
  } catch (const std::runtime_error&) {
  }
  // Nothing may be written outside the export's folder (an indicator's name makes a file name).
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name != "csv" && name != "base-0.h5" && name != "base-1.h5" && name != "input.h5" &&
        name != "resumed.h5" && name != "merged.h5") {
      finding("a file appeared outside the export's folder: " + entry.path().string());
    }
  }
  fs::remove_all(csv);
  resume(std::move(results), folder / "resumed.h5");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path file = fixture().folder / "input.h5";
  {
    const std::string bytes = mutated(data, size);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) finding("cannot write " + file.string());
  }
  try {
    read_every_way(file);
  } catch (const std::exception& e) {
    finding(std::string("a reader threw ") + typeid(e).name() +
            " (not its documented error): " + e.what());
  } catch (...) {
    finding("a reader threw something that is not a std::exception");
  }
  return 0;
}
