// `impactid run PLAN.toml [--threads N] [--output FILE] [--resume] [--dry-run]`: runs a plan
// and writes its results file; checkpoints while it runs; Ctrl-C or SIGTERM stops it cleanly
// with everything finished saved; --resume computes only what the file lacks.
// `impactid export FILE.h5 --csv DIR`: the same surfaces as CSV.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

std::function<int()> add_run_command(CLI::App& app);
std::function<int()> add_export_command(CLI::App& app);

}  // namespace impactid
