// `impactid simulate`: one scene, one method, the paper's indicators (human-readable or
// --json), optionally the time histories (--history FILE.csv|.h5).
// `impactid compare`: every method at its default parameters on one scene, as a table.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

/// Registers the subcommand; the returned function runs it after parsing and gives the exit
/// status.
std::function<int()> add_simulate_command(CLI::App& app);
std::function<int()> add_compare_command(CLI::App& app);

}  // namespace impactid
