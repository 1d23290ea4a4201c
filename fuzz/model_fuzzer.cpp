// libFuzzer target: a user's model (kind = "matrices", study/plan/model_file.hpp): a scene file
// and the files it names, read by parse_scene_file as `impactid simulate --scene` reads them.
//
// The input is split at each line "----" into the texts of, in order, scene.toml, M.mtx, K.mtx,
// C.mtx, u0.mtx (a Matrix Market vector) and reference.csv, written into a private folder before
// each run; a file the input does not reach is removed, so a run never sees an earlier input's
// files. The seeds name them as a model does (mass = "M.mtx", velocity = "u0.mtx",
// reference.file = "reference.csv").
//
// The contract under test: parse_scene_file() either returns settings that build() turns into a
// Simulation (the promise `impactid simulate` relies on), or throws PlanError naming the scene
// file. A crash, a sanitizer report, a hang, an out-of-memory or an exception of another type
// (MatrixMarketError escaping the model reader, std::bad_alloc from a size taken at its word…)
// is a finding.
//
// Run it with scripts/fuzz; seeds fuzz/corpus/model/, dictionary fuzz/toml.dict, fuzz/mtx.dict
// and fuzz/model.dict together.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "scene_file_contract.hpp"

namespace {

constexpr std::array<const char*, 5> kFiles{"M.mtx", "K.mtx", "C.mtx", "u0.mtx", "reference.csv"};
constexpr std::string_view kSeparator = "\n----\n";

// Writes the model's files of the input into `folder`; returns the scene's text.
std::string place_files(std::string_view input, const std::filesystem::path& folder) {
  std::size_t end = input.find(kSeparator);
  const std::string scene(input.substr(0, end));
  for (const char* name : kFiles) {
    const std::filesystem::path file = folder / name;
    if (end == std::string_view::npos) {
      std::error_code ec;
      std::filesystem::remove(file, ec);
      continue;
    }
    const std::size_t start = end + kSeparator.size();
    end = input.find(kSeparator, start);
    const std::string_view text =
        input.substr(start, end == std::string_view::npos ? end : end - start);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) fuzz::finding("model_fuzzer", "cannot write " + file.string());
  }
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fuzz::Folder folder("model_fuzzer");
  const std::string scene =
      place_files(std::string_view(reinterpret_cast<const char*>(data), size), folder.path);
  fuzz::check_scene_file("model_fuzzer", scene, folder.path / "scene.toml");
  return 0;
}
