// A grid or list plan's sweep over MPI ranks: `mpirun -np N impactid-mpi run PLAN.toml`
// (study/cli/main_mpi.cpp). A dedicated master, as Dakota's: rank 0 reads the plan and the existing
// results file (run_command.cpp, unchanged), hands the points out in batches, gathers their
// rows and writes the one results file with its checkpoints, progress and --resume as a single
// process does. Ranks 1..N−1 are workers that compute what they are given with their OpenMP
// threads.
//
// Work is handed out dynamically: a batch is as many windows of kBatchLanes points (the sweep's
// and the batched kernel's unit, study/studies/sweep.hpp) as the worker has threads, taken in order
// from the points still to compute. Each worker holds two batches, so it computes the second
// while rank 0 answers the first; every finished batch brings the next. Static splits would
// leave ranks idle: an unstable point stops early, so batches differ in cost. A worker's batch
// doubles while its round trip is short (cheap points), and shrinks near the end (mpi_sweep.cpp).
//
// Rank 0's main thread serves the workers (the one thread that calls MPI: MPI_THREAD_FUNNELED)
// and writes the checkpoints. When the job has at most kMasterComputesUpToRanks ranks, rank 0's
// --threads more threads compute windows too, taken one at a time from the same queue: there
// rank 0's cores are a quarter or more of the job. With more ranks rank 0 only serves, so that
// its answers, and the checkpoints of a large table, never wait for its own computing.
//
// Determinism: a point's numbers depend only on its flat index (study/studies/sweep.hpp), so the
// file is the single run's bit for bit (timing aside) for any number of ranks and threads.
//
// Errors: a worker that fails on a point (an exception while building or running it) reports
// the point and the message; rank 0 stops handing out work, collects what is still running,
// saves everything computed and fails the run with "rank R: point I (name =
// value, ...): message". A killed rank ends the job (mpirun); --resume continues from the
// last checkpoint. For tests, IMPACTID_MPI_FAIL_AT_POINT=I makes whichever rank computes
// point I fail on it.
//
// Stalls: a rank that stops answering without dying (SIGSTOP, a hung node) is not seen by
// mpirun. A batch out longer than a bound (a multiple of its expected time, with a floor:
// study/cli/mpi_stall.hpp, --stall-factor and --stall-min-seconds) is handed to another rank,
// rank 0's computing threads included; the first answer is kept, a late one is received and
// dropped. The file is the same. A rank still owing an answer when the sweep is over is given
// up on: it gets no more work, and at the end of the program rank 0 ends the job with
// MPI_Abort (study/cli/main_mpi.cpp) once the results file is written.
#pragma once

#include <atomic>
#include <functional>
#include <span>
#include <vector>

#include "study/cli/mpi_stall.hpp"
#include "study/io/results_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/optimizer.hpp"
#include "study/studies/sweep.hpp"

namespace impactid {

inline constexpr int kMasterComputesUpToRanks = 4;

/// Rank 0's side. One object for the life of the program; MPI must be initialised (at least
/// MPI_THREAD_FUNNELED) and every call made from the thread that initialised it.
class MpiMaster {
 public:
  MpiMaster();
  /// run_sweep's contract (SweepRunner, study/cli/run_command.hpp), over every rank.
  SweepOutcome run(const Plan& plan, const PointSet& points, std::span<const long> indices,
                   StudyResults& results, const SweepOptions& options);
  /// SearchRunner's contract (study/studies/optimizer.hpp): an optimisation's searches over
  /// every rank (study/cli/mpi_search.cpp). A search is handed out whole; a worker gets as many
  /// at a time as it has threads, and rank 0 runs them too under kMasterComputesUpToRanks. A
  /// stop hands out no more searches and waits for those running (each ends within its
  /// max_evaluations). A worker's error is thrown, as the sweep's. For tests,
  /// IMPACTID_MPI_FAIL_AT_SEARCH=S makes whichever rank runs search S fail on it, and
  /// IMPACTID_MPI_STOP_AFTER_ROWS=R stops rank R (SIGSTOP) between its first search's rows and
  /// that search's end (rank 0 must not wait for the end); IMPACTID_MPI_STOP_IN_ROWS=R, in the
  /// middle of its first rows message, of a batch or a search (mpi_protocol::send_rows).
  void run_searches(const Plan& plan, std::span<const long> starts,
                    std::span<const StudyResults> previous, const std::atomic<bool>* stop,
                    const std::function<void(long, SearchOutcome)>& done);
  /// Tells every worker to end and waits for each one's answer, at most stall.min_seconds.
  /// Once, before MPI_Finalize. Returns the ranks given up on (in a sweep, or silent here):
  /// MPI_Finalize would wait for them forever. When there are none, lets the workers go on to
  /// MPI_Finalize (serve_mpi_worker returns); otherwise they wait for the MPI_Abort.
  std::vector<int> release_workers();

  /// When work out at a worker is handed to another rank; set before run().
  mpi_protocol::StallOptions stall;

 private:
  int ranks_ = 1;
  /// Per rank: given up on; it is sent nothing more, and its messages are dropped.
  std::vector<char> lost_;
  /// Every message with data to a worker (sent without blocking: mpi_protocol.hpp).
  mpi_protocol::Outbox outbox_;
  /// Every message from a worker (received without blocking: mpi_protocol.hpp); one for the
  /// program, as a stalled rank's message may come whole in a later sweep.
  mpi_protocol::Inbox inbox_;
  /// Gives up on the ranks that still owe an answer at the end of a sweep or search, and says so.
  void give_up_on(const std::vector<int>& ranks, const char* what);
};

/// Ranks 1..N−1: serves the master until it releases the workers. Returns the exit status.
int serve_mpi_worker();

}  // namespace impactid
