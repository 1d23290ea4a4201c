// The results fuzzer's files (fuzz/results_fuzzer.cpp): its two base files, written by the
// program under test from a tiny plan, and an input's flips applied to one of them. Shared with
// tests/damaged_results_test.cpp, which replays the fuzzer's findings (fuzz/corpus/results/
// regression-*) on the same bytes.
//
// The input, bytes in order:
//   byte 0: bit 0 chooses the base; with bit 1 set the file is also truncated, to the length
//     (taken modulo the base's size + 1) in the next 3 bytes, little-endian;
//   then records of 3 bytes of offset (little-endian, modulo the file's size), 1 byte n, and
//     n % 8 + 1 bytes XORed into the file at the offset (one set bit is a bit flip; any byte
//     value can be written). An empty input reads a base unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <vector>

#include "study/io/results_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/practical_range.hpp"
#include "study/studies/shard.hpp"
#include "study/studies/sweep.hpp"

namespace impactid::fuzzing {

// A numeric axis and a choice axis (its labels are CF flag_meanings), a practical range and the
// verdict column: every kind of dataset and attribute a grid's file has.
inline constexpr const char* kBasePlan = R"(name = "fuzz"
[scene]
elements = 4
[method]
name = "newmark"
[study]
kind = "grid"
[study.axes]
delta = { values = [0.5, 0.7] }
contact = { values = ["lagrange", "penalty"] }
[study.practical]
eps_p = { max = 1.0 }
)";

/// Runs `plan` (kBasePlan) and writes its table twice into `folder`: base-0.h5 as `impactid run`
/// writes it, base-1.h5 compressed and marked as shard 0/1, as `impactid run --shard` writes it.
/// Returns the two files' bytes (empty if one cannot be read back).
inline std::vector<std::string> write_bases(const Plan& plan, const std::filesystem::path& folder) {
  const PointSet points(plan);
  StudyResults results = empty_results(plan, points);
  std::vector<long> all(static_cast<std::size_t>(points.size()));
  std::iota(all.begin(), all.end(), 0L);
  run_sweep(points, all, results, SweepOptions{});
  store_practical_range(results, practical_range(results, plan.practical));
  write_results(folder / "base-0.h5", results);
  mark_shard(results, Shard{0, 1}, plan.path);
  write_results_compressed(folder / "base-1.h5", results);
  std::vector<std::string> bases;
  for (const char* name : {"base-0.h5", "base-1.h5"}) {
    std::ifstream in(folder / name, std::ios::binary);
    bases.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return bases;
}

/// The base the input chooses with the input applied, as described above.
inline std::string apply_input(const std::vector<std::string>& bases, const std::uint8_t* data,
                               std::size_t size) {
  const auto little_endian = [](const std::uint8_t* p) -> std::size_t {
    return p[0] | (p[1] << 8) | (p[2] << 16);
  };
  std::string file = bases[size > 0 ? data[0] & 1 : 0];
  std::size_t at = 1;
  if (size > 0 && (data[0] & 2) && size >= 4) {
    file.resize(little_endian(data + 1) % (file.size() + 1));
    at = 4;
  }
  while (at + 4 <= size && !file.empty()) {
    const std::size_t offset = little_endian(data + at) % file.size();
    const std::size_t n = data[at + 3] % 8 + 1;
    at += 4;
    for (std::size_t k = 0; k < n && at < size && offset + k < file.size(); ++k, ++at) {
      file[offset + k] = static_cast<char>(file[offset + k] ^ data[at]);
    }
  }
  return file;
}

}  // namespace impactid::fuzzing
