// The results fuzzer's findings replayed (fuzz/corpus/results/regression-hdf5-*, applied to the
// fuzzer's own base files, fuzz/results_input.hpp): `impactid export` of each damaged file ends
// with a message naming the file, never with a crash, run as a separate process, as a user
// would; and in this process, each file read many times over, as a merge or a Python session
// reads one, is refused or read alike every time. HDF5 1.10's crashes on some of these files
// depend on what the heap held (the first reader's, or a later reader's after HDF5's free lists
// were damaged): HDF5 parses them only in the reader's child (study/formats/hdf5_file.hpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.hpp"
#include "study/formats/hdf5_file.hpp"
#include "fuzz/results_input.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("damaged_results_test", name);
}

// The fuzzer's findings as files: each fuzz/corpus/results/regression-hdf5-* input applied to
// the fuzzer's base files, written as SCRATCH/<name><suffix>.h5. Returns (name, file) pairs.
std::vector<std::pair<std::string, fs::path>> finding_files(const std::string& suffix) {
  const Plan plan = parse_plan(fuzzing::kBasePlan, scratch("fuzz" + suffix + ".toml"));
  const fs::path folder = scratch("bases" + suffix);
  fs::create_directories(folder);
  const std::vector<std::string> bases = fuzzing::write_bases(plan, folder);
  EXPECT_FALSE(bases[0].empty());
  EXPECT_FALSE(bases[1].empty());
  std::vector<std::pair<std::string, fs::path>> files;
  for (const auto& entry :
       fs::directory_iterator(fs::path(IMPACTID_SOURCE_DIR) / "fuzz" / "corpus" / "results")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("regression-hdf5-", 0) != 0) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string input{std::istreambuf_iterator<char>(in), {}};
    const fs::path file = scratch(name + suffix + ".h5");
    const std::string bytes = fuzzing::apply_input(
        bases, reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    files.emplace_back(name, file);
  }
  return files;
}

TEST(DamagedResults, EveryFindingOfTheResultsFuzzerIsRefusedByName) {
  // Under the sanitizers: HDF5's own leak on a damaged header (fuzz/lsan.supp says which) would
  // end every refusal with LeakSanitizer's report; the caller's LSAN_OPTIONS win.
  const std::string leaks =
      "suppressions=" + (fs::path(IMPACTID_SOURCE_DIR) / "fuzz" / "lsan.supp").string();
  ::setenv("LSAN_OPTIONS", leaks.c_str(), 0);
  int replayed = 0;
  for (const auto& [name, file] : finding_files("")) {
    const auto o = testing::run_impactid("export " + file.string() + " --csv " +
                                         scratch(name + "-csv").string());
    // A crash: -1 (the process did not exit), or 128 + the signal (the shell's report of it).
    // 0 is allowed: a flip that neither HDF5's checksums nor impactid's notice.
    EXPECT_TRUE(o.status >= 0 && o.status < 128) << name << ": status " << o.status << ":\n"
                                                 << o.text;
    if (o.status != 0) {
      EXPECT_NE(o.text.find(file.string()), std::string::npos) << o.text;
    }
    ++replayed;
  }
  EXPECT_GE(replayed, 7);  // the seeds of fuzz/corpus/results
}

// Each finding read 25 times in this process: the same refusal, or the same values, each time.
// While a reader of one lives, HDF5 holds no file of this process open: the walk ran elsewhere.
TEST(DamagedResults, EveryFindingReadOverAndOverInOneProcessGivesOneOutcome) {
  int refused = 0;
  for (const auto& [name, file] : finding_files("-again")) {
    std::string first;
    for (int round = 0; round < 25; ++round) {
      std::string outcome;
      try {
        const Hdf5Reader reader(file, UncheckedFile::quiet);
        EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE), 0) << name;
        const StudyResults results = read_results(file);
        outcome = "read " + std::to_string(results.status.size()) + " points";
      } catch (const std::exception& e) {
        outcome = e.what();
        EXPECT_NE(outcome.find(file.string()), std::string::npos) << outcome;
      }
      if (round == 0) first = outcome;
      EXPECT_EQ(outcome, first) << name << ", round " << round;
    }
    refused += first.rfind("read ", 0) != 0;
  }
  EXPECT_GE(refused, 7);
}

}  // namespace
}  // namespace impactid
