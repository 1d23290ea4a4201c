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
#include <unistd.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <typeinfo>
#include <variant>

#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 5> kFiles{"M.mtx", "K.mtx", "C.mtx", "u0.mtx", "reference.csv"};
constexpr std::string_view kSeparator = "\n----\n";

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "model_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

// A folder of the fuzzer's own, removed at exit.
struct Folder {
  fs::path path;
  Folder() {
    std::string pattern = (fs::temp_directory_path() / "impactid-model-fuzzer-XXXXXX").string();
    if (!mkdtemp(pattern.data())) finding("cannot create a temporary folder");
    path = pattern;
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Writes the model's files of the input into `folder`; returns the scene's text.
std::string place_files(std::string_view input, const fs::path& folder) {
  std::size_t end = input.find(kSeparator);
  const std::string scene(input.substr(0, end));
  for (const char* name : kFiles) {
    const fs::path file = folder / name;
    if (end == std::string_view::npos) {
      std::error_code ec;
      fs::remove(file, ec);
      continue;
    }
    const std::size_t start = end + kSeparator.size();
    end = input.find(kSeparator, start);
    const std::string_view text = input.substr(start, end == std::string_view::npos ? end : end - start);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) finding("cannot write " + file.string());
  }
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Folder folder;
  const std::string scene =
      place_files(std::string_view(reinterpret_cast<const char*>(data), size), folder.path);
  const fs::path source = folder.path / "scene.toml";
  impactid::SimulationSettings settings;
  try {
    settings = impactid::parse_scene_file(scene, source);
  } catch (const impactid::PlanError& e) {
    if (std::string(e.what()).rfind(source.string(), 0) != 0) {
      finding(std::string("a PlanError that does not name the scene file: ") + e.what());
    }
    return 0;
  } catch (const std::exception& e) {
    finding(std::string("parse_scene_file threw ") + typeid(e).name() + " (not PlanError): " +
            e.what());
  } catch (...) {
    finding("parse_scene_file threw something that is not a std::exception");
  }
  try {
    const auto built = impactid::build(settings);
    if (const auto* error = std::get_if<impactid::ParameterError>(&built)) {
      finding("parse_scene_file accepted a model that does not build: " + error->field + " = " +
              error->value + ": " + error->constraint);
    }
  } catch (const std::exception& e) {
    finding(std::string("build() of a parsed model threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}
