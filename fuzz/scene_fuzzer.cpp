// libFuzzer target: any bytes as a scene file, `impactid simulate --scene FILE.toml`
// (study/plan/scene_file.hpp, study/plan/plan.hpp: parse_scene_file): the rod's keys, a scene of
// bodies ([[scene.body]], [scene.wall.*]) or a model (kind = "matrices"), at the root or under
// [scene]. The file is read as <a private empty folder>/scene.toml, so a model's matrix files
// are missing there (model_fuzzer gives them).
//
// The contract under test: parse_scene_file() either returns settings or throws PlanError, whose
// message names the file. A returned scene's promise ("checked by build() with the default
// method") is checked: build() gives a Simulation, as `impactid simulate` relies on. A crash, a
// sanitizer report, a hang, an out-of-memory or an exception of another type is a finding.
//
// Run it with scripts/fuzz; seeds fuzz/corpus/scene/ and examples/*/scene.toml, dictionary
// fuzz/toml.dict.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <typeinfo>
#include <variant>

#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "scene_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

// An empty folder of the fuzzer's own, removed at exit.
struct Folder {
  fs::path path;
  Folder() {
    std::string pattern = (fs::temp_directory_path() / "impactid-scene-fuzzer-XXXXXX").string();
    if (!mkdtemp(pattern.data())) finding("cannot create a temporary folder");
    path = pattern;
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Folder folder;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const fs::path source = folder.path / "scene.toml";
  impactid::SimulationSettings settings;
  try {
    settings = impactid::parse_scene_file(text, source);
  } catch (const impactid::PlanError& e) {
    if (std::string(e.what()).rfind(source.string(), 0) != 0) {
      finding(std::string("a PlanError that does not name the file: ") + e.what());
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
      finding("parse_scene_file accepted a scene that does not build: " + error->field + " = " +
              error->value + ": " + error->constraint);
    }
  } catch (const std::exception& e) {
    finding(std::string("build() of a parsed scene threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}
