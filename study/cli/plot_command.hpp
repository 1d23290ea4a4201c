// `impactid plot FILE.h5 [--out DIR] [--format png|pdf]`: draws any file impactid writes (a
// results file of any study kind, a spectral file, a history file) by running the project's
// figure package (figures/plot_results.py, figures/impactid_figures/own_results.py) with
// Debian's /usr/bin/python3 (IMPACTID_PYTHON overrides it).
//
// The package is looked for, in this order, in IMPACTID_FIGURES_DIR (a folder holding
// plot_results.py), beside an installed program (<prefix>/bin/impactid finds
// <prefix>/share/impactid/figures, which `cmake --install` puts there) and in the source tree the
// program was built from. A missing Python, package or matplotlib ends with a message that says
// what is missing and how to get it, and exit status 1; a file that is not impactid's, exit 2.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace impactid {

std::function<int()> add_plot_command(CLI::App& app);

/// The folder of plot_results.py by the rules above, or nothing; `tried` gets the folders looked
/// at, for the message.
std::optional<std::filesystem::path> find_figures_dir(std::string& tried);

}  // namespace impactid
