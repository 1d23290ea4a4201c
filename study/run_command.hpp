// `impactid run PLAN.toml [--threads N] [--output FILE] [--resume] [--dry-run]`: runs a plan
// and writes its results file; checkpoints while it runs; Ctrl-C or SIGTERM stops it cleanly
// with everything finished saved; --resume computes only what the file lacks.
// `impactid export FILE.h5 --csv DIR`: the same surfaces as CSV.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <span>

#include "study/sweep.hpp"

namespace impactid {

/// How the points of a grid or list plan are computed: by default run_sweep (the threads of
/// this process); impactid-mpi passes its master (study/mpi_sweep.hpp), which hands them out to
/// other ranks. Same contract as run_sweep.
using SweepRunner = std::function<SweepOutcome(const Plan&, const PointSet&, std::span<const long>,
                                               StudyResults&, const SweepOptions&)>;

std::function<int()> add_run_command(CLI::App& app, SweepRunner runner = {});
std::function<int()> add_export_command(CLI::App& app);

}  // namespace impactid
