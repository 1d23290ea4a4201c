// A user's model in a scene file or a plan's [scene] table (issue 20), `kind = "matrices"`: M, K
// and C as Matrix Market files ([scene.matrices]), named DOF sets ([scene.dof_sets]), the initial
// state ([scene.initial]), a constant load ([scene.load]), the contacts ([[scene.contact]]: a wall
// on one DOF or a pair of DOFs) and an optional reference history ([scene.reference]). Every key,
// its default, unit and refusal, with a complete example (examples/three-dof/) and how to export M
// and K from GetFEM, dolfinx, Code_Aster and OpenSees: docs/model-files.md, which
// tests/model_files_doc_test.py holds to this reader's messages.
//
// DOFs count from 0 (a Matrix Market row minus one); paths are relative to the file of the table.
// Every error names the file, the line, the key and the value (a PlanError through `fail`).
// dt, t_end and the Rayleigh factors are scene parameters, read with the other scenes' (sweep
// axes); the rest is read here. Large files are read with a progress line on a terminal.
#pragma once

#include <toml++/toml.h>

#include <filesystem>
#include <string>

#include "core/model/model_scene.hpp"
#include "study/plan/scene_file.hpp"

namespace impactid {

/// Whether a [scene] table describes a model (kind = "matrices").
bool is_model_scene(const toml::table& scene);
/// Whether `key` of a [scene] table belongs to the model's description rather than to the
/// whole-scene parameters (dt, t_end, rayleigh_*).
bool is_model_scene_key(const std::string& key);

/// Reads and checks the model of a [scene] table; `prefix` is the table's dotted key
/// ("scene"), `directory` the folder its paths are relative to. `fail` must throw. dt, t_end and
/// the Rayleigh factors are left to the caller (they are sweepable parameters).
ModelScene read_model_scene(const toml::table& scene, const std::string& prefix,
                            const std::filesystem::path& directory, const TableFail& fail);

}  // namespace impactid
