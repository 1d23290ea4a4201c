// `impactid run PLAN.toml [--threads N] [--output FILE] [--resume] [--dry-run]`: runs a plan
// and writes its results file; checkpoints while it runs; Ctrl-C or SIGTERM stops it cleanly
// with everything finished saved; --resume computes only what the file lacks.
// `impactid export FILE.h5 --csv DIR`: the same surfaces as CSV.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <span>
#include <string>

#include "study/studies/optimizer.hpp"
#include "study/studies/sweep.hpp"

namespace impactid {

/// What `impactid run` is given.
struct RunArguments {
  std::string plan;  ///< the plan file; with plan_text, the name its messages give it
  /// When not empty, the plan itself (python/: a plan given as a dict), read as parse_plan reads
  /// a file's text; `plan` is then not opened.
  std::string plan_text;
  std::string output;
  int threads = 0;
  bool resume = false;
  bool dry_run = false;
  bool force = false;  ///< replace a results file that holds another shard or another plan's shard
  std::string shard;  ///< "K/N", or "" (then a Slurm array task's, or the whole plan)
};

/// How the points of a grid or list plan are computed: by default run_sweep (the threads of
/// this process); impactid-mpi passes its master (study/cli/mpi_sweep.hpp), which hands them out
/// to other ranks. Same contract as run_sweep.
using SweepRunner = std::function<SweepOutcome(const Plan&, const PointSet&, std::span<const long>,
                                               StudyResults&, const SweepOptions&)>;

/// Where a plan's work runs: unset members run on this process's threads.
struct Runners {
  SweepRunner sweep;      ///< a grid's or list's points
  SearchRunner searches;  ///< an optimisation's searches (study/studies/optimizer.hpp)
  /// How a user continues a stopped run, before the plan's name in the hint on stderr:
  /// impactid-mpi gives its own ("mpirun -np 4 impactid-mpi run").
  std::string resume_command = "impactid run";
  /// Adds the runners' own options to the `run` command (impactid-mpi: when a stalled rank's
  /// work is handed on).
  std::function<void(CLI::App& run)> add_options;
};

/// Runs a plan as `impactid run` does: progress and the summary on stderr, every error on
/// std::cerr; SIGINT and SIGTERM stop it with what is finished saved (the previous handlers come
/// back when it returns). Returns the exit status: 0, kExitBadInput, kExitFailure, or 130 when
/// it was interrupted.
int run_plan(const RunArguments& args, const Runners& runners = {});

std::function<int()> add_run_command(CLI::App& app, Runners runners = {});
std::function<int()> add_export_command(CLI::App& app);

}  // namespace impactid
