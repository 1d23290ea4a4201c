// What scene_fuzzer and model_fuzzer check of one scene file: parse_scene_file() (study/plan/
// plan.hpp) either returns settings or throws PlanError, whose message names the file, and a
// returned scene keeps its promise ("checked by build() with the default method"): build() gives
// a Simulation, as `impactid simulate` relies on. Anything else is a finding: the fuzzer names
// it on stderr and aborts, and libFuzzer saves the input as crash-<sha1>.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <typeinfo>
#include <variant>

#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace fuzz {

[[noreturn]] inline void finding(const char* fuzzer, const std::string& what) {
  std::fprintf(stderr, "%s: FINDING: %s\n", fuzzer, what.c_str());
  std::abort();
}

/// An empty folder of the fuzzer's own, removed at exit.
struct Folder {
  std::filesystem::path path;
  explicit Folder(const char* fuzzer) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / (std::string("impactid-") + fuzzer + "-XXXXXX"))
            .string();
    if (!mkdtemp(pattern.data())) finding(fuzzer, "cannot create a temporary folder");
    path = pattern;
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

/// Reads `text` as the scene file `source` and checks the contract above.
inline void check_scene_file(const char* fuzzer, const std::string& text,
                             const std::filesystem::path& source) {
  impactid::SimulationSettings settings;
  try {
    settings = impactid::parse_scene_file(text, source);
  } catch (const impactid::PlanError& e) {
    if (std::string(e.what()).rfind(source.string(), 0) != 0) {
      finding(fuzzer, std::string("a PlanError that does not name the scene file: ") + e.what());
    }
    return;
  } catch (const std::exception& e) {
    finding(fuzzer, std::string("parse_scene_file threw ") + typeid(e).name() +
                        " (not PlanError): " + e.what());
  } catch (...) {
    finding(fuzzer, "parse_scene_file threw something that is not a std::exception");
  }
  try {
    const auto built = impactid::build(settings);
    if (const auto* error = std::get_if<impactid::ParameterError>(&built)) {
      finding(fuzzer, "parse_scene_file accepted a scene that does not build: " + error->field +
                          " = " + error->value + ": " + error->constraint);
    }
  } catch (const std::exception& e) {
    finding(fuzzer,
            std::string("build() of a parsed scene threw ") + typeid(e).name() + ": " + e.what());
  }
}

}  // namespace fuzz
