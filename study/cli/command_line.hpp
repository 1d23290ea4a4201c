// Shared pieces of the `impactid` subcommands: how a parameter of the settings table becomes a
// command-line option, and how a bad value is reported (exit status 2, option and value named).
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "study/plan/simulation_settings.hpp"

namespace impactid {

/// Exit status for bad input (command line, plan file).
inline constexpr int kExitBadInput = 2;
/// Exit status for a failure while working (I/O, a results file that cannot be written).
inline constexpr int kExitFailure = 1;
/// Exit status of `simulate` and `compare` when a run's reference is not trusted (verdict
/// `unverified` for want of a trusted reference: core/reference/model_reference.hpp), so that a
/// script does not take an unjudged number for a result.
inline constexpr int kExitUnverified = 3;

/// "youngs_modulus" -> "--youngs-modulus"
std::string option_name(const std::string& parameter);

/// Options given on the command line, by parameter name, as text.
using GivenOptions = std::map<std::string, std::string>;

/// Adds one option per parameter of the table in the given groups, with unit, default and
/// range in its help text. Values land in `given` only when the user passes them.
void add_parameter_options(CLI::App& command, GivenOptions& given,
                           std::initializer_list<ParameterGroup> groups);

/// Applies the given options to the settings; on error prints "impactid <command>: --name =
/// value: constraint" to stderr and returns false.
bool apply_options(const GivenOptions& given, SimulationSettings& settings,
                   const std::string& command);
/// `--scene FILE.toml` (a scene file, study/plan/scene_file.hpp) and `--set KEY=VALUE` (a dotted
/// key of a scene of bodies, study/plan/scene_path.hpp; repeatable), for the commands that run a
/// scene.
struct SceneOptions {
  std::string file;
  std::vector<std::string> set;
};
void add_scene_options(CLI::App& command, SceneOptions& options);
/// Reads the scene file into `settings` (replacing them) and applies the --set keys; on error
/// prints the file's message or "impactid <command>: key = value: constraint" and returns false.
bool apply_scene_options(const SceneOptions& options, SimulationSettings& settings,
                         const std::string& command);

/// Builds the simulation; on error prints the message as above and returns nothing.
std::optional<Simulation> build_or_report(const SimulationSettings& settings,
                                          const std::string& command);
void report(const ParameterError& error, const std::string& command);

}  // namespace impactid
