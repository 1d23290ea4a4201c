// libFuzzer target: any bytes as a scene file, `impactid simulate --scene FILE.toml`
// (study/plan/scene_file.hpp, study/plan/plan.hpp: parse_scene_file): the rod's keys, a scene of
// bodies ([[scene.body]], [scene.wall.*]) or a model (kind = "matrices"), at the root or under
// [scene]. The file is read as <a private empty folder>/scene.toml, so a model's matrix files
// are missing there (model_fuzzer gives them).
//
// The contract under test: fuzz/scene_file_contract.hpp. A crash, a sanitizer report, a hang or an
// out-of-memory is a finding too.
//
// Run it with scripts/fuzz; seeds fuzz/corpus/scene/ and examples/*/scene.toml, dictionary
// fuzz/toml.dict.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene_file_contract.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fuzz::Folder folder("scene_fuzzer");
  fuzz::check_scene_file("scene_fuzzer", std::string(reinterpret_cast<const char*>(data), size),
                         folder.path / "scene.toml");
  return 0;
}
