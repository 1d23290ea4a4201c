// `impactid export-model`: any built-in scene (the paper's rod, a scene of bodies) written as a
// user's model (study/plan/model_file.hpp) — M, K and C as Matrix Market files, a scene file of
// kind "matrices" with its contacts, initial state, load (gravity), step and end time, and, when
// the scene has an exact solution, that solution at the run's samples as the model's reference
// history. The
// exported model runs the built-in scene's operations (core/model/model_scene.hpp), so a plan on it
// gives the built-in scene's numbers: the path from a user's files to a results file, proved end to
// end.
//
// Numbers are written with 17 significant digits: they read back to the same doubles.
//
// Thread safety: free functions.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>

#include "study/plan/simulation_settings.hpp"

namespace impactid {

/// Writes DIRECTORY/{M.mtx, K.mtx, C.mtx (damped scenes), v0.mtx (bodies of several velocities),
/// u0.mtx (displaced bodies), f.mtx (gravity's load),
/// scene.toml, reference.csv (exact scenes)} for a valid built-in simulation's scene. Throws
/// std::runtime_error naming the file it could not write, or for a model (already matrices).
void export_model(const Simulation& simulation, const std::filesystem::path& directory);

std::function<int()> add_export_model_command(CLI::App& app);

}  // namespace impactid
