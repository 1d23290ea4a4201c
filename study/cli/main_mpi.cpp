// impactid-mpi: the impactid program for MPI jobs, `mpirun -np N impactid-mpi run PLAN.toml`.
// Every command works as in impactid; `run` of a grid or list plan hands its points out over
// the ranks (study/cli/mpi_sweep.hpp). Rank 0 parses the command line and does everything a single
// process does, the other ranks compute what it sends them. Run without mpirun, or on one rank,
// it is impactid.
#include <mpi.h>

#include <cstdio>
#include <string>

#include "study/cli/cli_main.hpp"
#include "study/cli/mpi_sweep.hpp"

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
  if (ranks == 1) {
    status = impactid::impactid_main(argc, argv);
  } else if (rank == 0) {
    impactid::MpiMaster master;
    impactid::Runners runners;
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
    status = impactid::impactid_main(argc, argv, runners);
    master.release_workers();
  } else {
    status = impactid::serve_mpi_worker();
  }
  MPI_Finalize();
  return status;
}
