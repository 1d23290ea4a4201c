// impactid-mpi: the impactid program for MPI jobs, `mpirun -np N impactid-mpi run PLAN.toml`.
// Every command works as in impactid; `run` of a grid or list plan hands its points out over
// the ranks (study/cli/mpi_sweep.hpp). Rank 0 parses the command line and does everything a single
// process does, the other ranks compute what it sends them. Run without mpirun, or on one rank,
// it is impactid (its `run` options --stall-factor and --stall-min-seconds accepted, unused).
#include <mpi.h>

#include <cstdio>
#include <string>

#include "study/cli/cli_main.hpp"
#include "study/cli/mpi_sweep.hpp"

namespace {

// impactid-mpi run's options on work handed on from a stalled rank (study/cli/mpi_stall.hpp).
void add_stall_options(CLI::App& run, impactid::mpi_protocol::StallOptions& stall) {
  run.add_option("--stall-factor", stall.factor,
                 "Hand a batch (or a search) out at a rank to another rank once it has been out "
                 "longer than this many times its expected time (its rounds of one window of 16 "
                 "points, or one search, per thread, times the slowest such round measured so "
                 "far), and at least --stall-min-seconds; the first answer is kept")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1e9))
      ->type_name("F");
  run.add_option("--stall-min-seconds", stall.min_seconds,
                 "Never hand work on before it has been out this long; also how long the end of "
                 "the run waits for a rank's last answer")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 1e9))
      ->type_name("S");
}

}  // namespace

int main(int argc, char** argv) {
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    std::fprintf(stderr,
                 "impactid-mpi: this MPI library does not support MPI_THREAD_FUNNELED "
                 "(OpenMP threads beside MPI calls from the main thread)\n");
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int status = 0;
  if (rank == 0) {
    impactid::MpiMaster master;
    impactid::Runners runners;
    runners.add_options = [&master](CLI::App& run) { add_stall_options(run, master.stall); };
    if (ranks > 1) {
      runners.sweep = [&master](const impactid::Plan& plan, const impactid::PointSet& points,
                                std::span<const long> indices, impactid::StudyResults& results,
                                const impactid::SweepOptions& options) {
        return master.run(plan, points, indices, results, options);
      };
      runners.searches = [&master](const impactid::Plan& plan, std::span<const long> starts,
                                   std::span<const impactid::StudyResults> previous,
                                   const std::atomic<bool>* stop, const auto& done) {
        master.run_searches(plan, starts, previous, stop, done);
      };
      runners.resume_command = "mpirun -np " + std::to_string(ranks) + " impactid-mpi run";
    }
    status = impactid::impactid_main(argc, argv, runners);
    const std::vector<int> silent = ranks > 1 ? master.release_workers() : std::vector<int>{};
    if (!silent.empty()) {
      // A rank that stopped answering (SIGSTOP, a hung node) would keep MPI_Finalize, and so the
      // job, waiting forever. The results file is written and closed by now (impactid_main has
      // returned), so the job ends here: MPI_Abort makes mpirun kill every rank, the silent ones
      // included, and mpirun exits with `status`, the run's own. That status is 0 when every
      // point is computed and saved: the file is complete and the same as an uninterrupted
      // run's, and a script or scheduler should go on with it; the rank is named above and here.
      std::string names;
      for (const int r : silent) names += (names.empty() ? "" : ", ") + std::to_string(r);
      std::fprintf(stderr,
                   "impactid-mpi: rank(s) %s stopped answering; the results are written; ending "
                   "the job with MPI_Abort (status %d) rather than waiting for them\n",
                   names.c_str(), status);
      std::fflush(stderr);
      MPI_Abort(MPI_COMM_WORLD, status);
    }
  } else {
    status = impactid::serve_mpi_worker();
  }
  MPI_Finalize();
  return status;
}
