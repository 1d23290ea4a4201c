// Files for tests that write plans and results files: where they go, and a small plan.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace impactid::testing {

/// TempDir()/impactid_<suite>_<pid>/<name>, with any earlier file or folder of that name
/// removed: one folder per test process, so parallel ctest runs and other users do not collide.
inline std::filesystem::path scratch_path(const std::string& suite, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("impactid_" + suite + "_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::remove_all(dir / name);
  return dir / name;
}

/// Writes `bytes` to `path` and returns the path.
inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// A grid plan of five HHT points along δ = −1.5α on a 30-element rod: a results file in a
/// few tens of milliseconds.
inline constexpr const char* kSmallPlan = R"(
[scene]
elements = 30
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 4 }
delta = "-1.5*alpha"
)";

}  // namespace impactid::testing
