#include "study/cli/mpi_sweep.hpp"

#include <mpi.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/cli/mpi_protocol.hpp"

namespace impactid {
namespace {

using namespace mpi_protocol;

// Batch sizing: a batch starts at one window per worker thread and doubles while its round
// trip is shorter than this, up to kMaxBatchWindows windows. Cheap points (a coarse rod) would
// otherwise cost a message per few milliseconds of work, and rank 0's answers, not the points,
// would set the pace.
constexpr double kBatchRoundTripSeconds = 0.25;
constexpr long kMaxBatchWindows = 4096;

std::size_t row_width(const StudyResults& r) {
  return 2 + r.parameters.size() + r.indicators.size();  // index, status, columns
}

// "point 17 (alpha = -0.3, delta = 0.45)"
std::string point_text(const PointSet& points, long index) {
  std::string text = "point " + std::to_string(index);
  const std::vector<double> values = points.parameter_values(index);
  const auto& names = points.parameter_names();
  for (std::size_t k = 0; k < names.size() && k < values.size(); ++k) {
    text += (k ? ", " : " (") + names[k] + " = " + format_value(values[k]);
  }
  return text + (names.empty() ? "" : ")");
}

// The test hook of the header: the point a worker fails on, or −1.
long injected_failure_point() {
  const char* text = std::getenv("IMPACTID_MPI_FAIL_AT_POINT");
  return text ? std::atol(text) : -1;
}

// Runs a window (evaluate_window); on an exception, the point that throws and its message,
// "point I (name = value, ...): what", found by running the window's points one at a time.
std::optional<std::string> evaluate_window_checked(const PointSet& points,
                                                   std::span<const long> window,
                                                   WindowWorkspace& workspace) {
  static const long fail_at = injected_failure_point();
  const auto run_one = [&](long index) {
    if (index == fail_at) {
      throw std::runtime_error("failure injected by IMPACTID_MPI_FAIL_AT_POINT=" +
                               std::to_string(fail_at));
    }
    evaluate_window(points, std::span(&index, 1), workspace);
  };
  try {
    if (fail_at < 0) {
      evaluate_window(points, window, workspace);
      return std::nullopt;
    }
    for (const long index : window) {
      if (index == fail_at) run_one(index);
    }
    evaluate_window(points, window, workspace);
    return std::nullopt;
  } catch (const std::exception&) {
  }
  for (const long index : window) {
    try {
      run_one(index);
    } catch (const std::exception& e) {
      return point_text(points, index) + ": " + e.what();
    }
  }
  return point_text(points, window.front()) +
         ": the window of points failed together, but each alone did not";
}

// --- the worker ------------------------------------------------------------------------------

// A plan being served: its points, a row buffer for one batch, one workspace per thread.
struct WorkerPlan {
  Plan plan;
  std::optional<PointSet> points;
  int threads = 1;
  StudyResults rows;
  std::vector<WindowWorkspace> workspaces;
};

// Computes a batch into w.rows (row k = indices[k]); the first failure, as "point I: what".
std::optional<std::string> compute_batch(WorkerPlan& w, const std::vector<long>& indices) {
  const long count = static_cast<long>(indices.size());
  const long windows = (count + kBatchLanes - 1) / kBatchLanes;
  std::optional<std::pair<long, std::string>> failure;  // the first failing window's message
#pragma omp parallel for schedule(dynamic, 1) num_threads(w.threads)
  for (long v = 0; v < windows; ++v) {
    WindowWorkspace& workspace = w.workspaces[static_cast<std::size_t>(omp_get_thread_num())];
    const long first = v * kBatchLanes;
    const auto size = static_cast<std::size_t>(std::min<long>(kBatchLanes, count - first));
    const std::span window(indices.data() + first, size);
    if (auto error = evaluate_window_checked(*w.points, window, workspace)) {
#pragma omp critical(impactid_mpi_failure)
      if (!failure || first < failure->first) failure.emplace(first, std::move(*error));
      continue;
    }
    for (std::size_t k = 0; k < size; ++k) {
      store_point_row(w.rows, static_cast<std::size_t>(first) + k, *w.points, window[k],
                      workspace.simulations[k], workspace.evaluations[k]);
    }
  }
  if (!failure) return std::nullopt;
  return failure->second;
}

void send_rows(const WorkerPlan& w, const std::vector<long>& indices) {
  const StudyResults& r = w.rows;
  std::vector<double> packed;
  packed.reserve(indices.size() * row_width(r));
  for (std::size_t k = 0; k < indices.size(); ++k) {
    packed.push_back(static_cast<double>(indices[k]));
    packed.push_back(r.status[k]);
    for (const ResultColumn& c : r.parameters) packed.push_back(c.values[k]);
    for (const ResultColumn& c : r.indicators) packed.push_back(c.values[k]);
  }
  MPI_Send(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, 0, kTagResult,
           MPI_COMM_WORLD);
}

}  // namespace

int serve_mpi_worker() {
  // mpirun passes SIGUSR1 to every rank; it is rank 0's to stop the run
  // (study/cli/run_command.cpp), and a worker stops when rank 0 has no more work for it.
  std::signal(SIGUSR1, SIG_IGN);
  const std::string rank = "rank " + std::to_string(world_rank());
  std::optional<WorkerPlan> served;
  for (;;) {
    MPI_Status probed;
    MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &probed);
    switch (probed.MPI_TAG) {
      case kTagPlan: {
        const std::string message = receive_text(probed);
        const std::size_t split = message.find('\0');
        served.emplace();
        WorkerPlan& w = *served;
        try {
          w.plan = parse_plan(message.substr(split + 1), message.substr(0, split));
          if (w.plan.kind != StudyKind::optimize) w.points.emplace(w.plan);
        } catch (const std::exception& e) {
          send_text(rank + ": the plan does not load here: " + e.what(), 0, kTagError);
          served.reset();
          break;
        }
        w.threads = std::max(1, omp_get_max_threads());
        if (w.points) {
          w.rows =
              empty_results(w.plan, *w.points, static_cast<std::size_t>(w.threads) * kBatchLanes);
          w.workspaces.resize(static_cast<std::size_t>(w.threads));
        }
        MPI_Send(&w.threads, 1, MPI_INT, 0, kTagReady, MPI_COMM_WORLD);
        break;
      }
      case kTagWork: {
        const std::vector<long> indices = receive_array<long>(probed, MPI_LONG);
        if (!served) break;  // the plan failed to load here; rank 0 knows and is stopping
        if (indices.size() > served->rows.status.size()) {  // rank 0 made the batches larger
          served->rows = empty_results(served->plan, *served->points, indices.size());
        }
        if (const auto error = compute_batch(*served, indices)) {
          send_text(rank + ": " + *error, 0, kTagError);
        } else {
          send_rows(*served, indices);
        }
        break;
      }
      case kTagSearches: {
        const std::vector<double> searches = receive_array<double>(probed, MPI_DOUBLE);
        if (!served) break;  // as for kTagWork
        serve_searches(served->plan, served->threads, searches);
        break;
      }
      case kTagEndSweep:
        MPI_Recv(nullptr, 0, MPI_CHAR, 0, kTagEndSweep, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        served.reset();
        break;
      case kTagStop:
        MPI_Recv(nullptr, 0, MPI_CHAR, 0, kTagStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        return 0;
      default: {
        receive_text(probed);  // not ours: drop it
        std::fprintf(stderr, "impactid-mpi: %s: unexpected message tag %d from rank 0\n",
                     rank.c_str(), probed.MPI_TAG);
        return kExitFailure;
      }
    }
  }
}

// --- the master ------------------------------------------------------------------------------

MpiMaster::MpiMaster() {
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
}

void MpiMaster::release_workers() {
  for (int r = 1; r < ranks_; ++r) MPI_Send(nullptr, 0, MPI_CHAR, r, kTagStop, MPI_COMM_WORLD);
}

SweepOutcome MpiMaster::run(const Plan& plan, const PointSet& points, std::span<const long> indices,
                            StudyResults& results, const SweepOptions& options) {
  if (ranks_ == 1) return run_sweep(points, indices, results, options);
  const auto start = Clock::now();
  SweepOutcome outcome;
  const std::vector<long> todo = points_to_compute(indices, results, outcome.reused);
  const long count = static_cast<long>(todo.size());
  const long window_count = (count + kBatchLanes - 1) / kBatchLanes;
  const std::size_t width = row_width(results);

  // The path in full: a worker on another node may start in another folder.
  const std::string plan_message = std::filesystem::absolute(plan.path).string() + '\0' + plan.text;
  for (int r = 1; r < ranks_; ++r) send_text(plan_message, r, kTagPlan);

  // Shared by rank 0's threads: thread 0 serves the workers (the only thread that calls MPI,
  // as MPI_THREAD_FUNNELED asks), the others compute windows when rank 0 computes. The mutex
  // guards `results` and everything below it.
  std::mutex mutex;
  std::vector<int> threads_of(static_cast<std::size_t>(ranks_), 0);      // 0 until Ready
  std::vector<long> batch_windows(static_cast<std::size_t>(ranks_), 0);  // its batch size now
  std::vector<std::deque<Clock::time_point>> sent_at(static_cast<std::size_t>(ranks_));
  std::vector<long> out(static_cast<std::size_t>(ranks_), 0);          // batches out per worker
  std::vector<long> computed_by(static_cast<std::size_t>(ranks_), 0);  // points per rank
  long next_window = 0, done = 0, unstable = 0, out_total = 0;
  int ready = 0;  // workers that answered the plan (Ready or an error)
  std::optional<std::string> error;
  const auto stopping = [&] { return error || (options.stop && options.stop->load()); };

  // Sends the worker its next batch, if any is left. Thread 0, mutex held. Near the end batches
  // shrink (a share of what is left, but at least a window per thread), so that no worker gets
  // a large last batch while the others wait.
  const auto give = [&](int worker) {
    if (stopping() || next_window >= window_count) return;
    const auto w = static_cast<std::size_t>(worker);
    const long left = window_count - next_window;
    const long windows =
        std::min({batch_windows[w], left, std::max<long>(threads_of[w], left / (2L * ranks_))});
    const long first = next_window * kBatchLanes;
    const long last = std::min(count, (next_window + windows) * kBatchLanes);
    MPI_Send(todo.data() + first, static_cast<int>(last - first), MPI_LONG, worker, kTagWork,
             MPI_COMM_WORLD);
    ++out[w];
    sent_at[w].push_back(Clock::now());
    ++out_total;
    next_window += windows;
  };

  // Handles one message from a worker if one waits. Thread 0.
  const auto handle = [&]() -> bool {
    const std::optional<MPI_Status> waiting = waiting_message();
    if (!waiting) return false;
    const MPI_Status& probed = *waiting;
    const int worker = probed.MPI_SOURCE;
    const auto w = static_cast<std::size_t>(worker);
    switch (probed.MPI_TAG) {
      case kTagReady: {
        const int threads = receive_ready(probed);
        std::lock_guard lock(mutex);
        threads_of[w] = threads;
        batch_windows[w] = threads_of[w];
        ++ready;
        give(worker);
        give(worker);  // the second batch, computed while rank 0 answers the first
        break;
      }
      case kTagResult: {
        const std::vector<double> packed = receive_array<double>(probed, MPI_DOUBLE);
        std::lock_guard lock(mutex);
        if (packed.size() % width != 0) {
          error = "rank " + std::to_string(worker) + " sent rows of another width (" +
                  std::to_string(packed.size()) + " values for rows of " + std::to_string(width) +
                  ")";
        }
        for (std::size_t at = 0; !error && at < packed.size(); at += width) {
          const auto i = static_cast<std::size_t>(packed[at]);
          results.status[i] = static_cast<int>(packed[at + 1]);
          std::size_t c = at + 2;
          for (ResultColumn& column : results.parameters) column.values[i] = packed[c++];
          for (ResultColumn& column : results.indicators) column.values[i] = packed[c++];
          ++done;
          ++computed_by[w];
          if (results.status[i] != 0) ++unstable;
        }
        if (out[w] > 0) --out[w], --out_total;
        if (!sent_at[w].empty()) {
          // Cheap points: double the batch until a batch's round trip (its own time plus the
          // wait behind the one before it) reaches kBatchRoundTripSeconds.
          const double round_trip = seconds_since(sent_at[w].front());
          sent_at[w].pop_front();
          if (round_trip < kBatchRoundTripSeconds && batch_windows[w] < kMaxBatchWindows) {
            batch_windows[w] *= 2;
          }
        }
        give(worker);
        break;
      }
      case kTagError: {
        const std::string message = receive_text(probed);
        std::lock_guard lock(mutex);
        if (!error) error = message;
        if (threads_of[w] == 0) {
          ++ready;  // it failed on the plan, before Ready
        } else if (out[w] > 0) {
          --out[w], --out_total;
          if (!sent_at[w].empty()) sent_at[w].pop_front();
        }
        break;
      }
      default: {
        std::string unexpected = receive_unexpected(probed);
        std::lock_guard lock(mutex);
        if (!error) error = std::move(unexpected);
      }
    }
    return true;
  };

  auto last_checkpoint = Clock::now(), last_progress = Clock::now();
  const bool log_lines = !isatty(2);  // mpirun's stderr is a pipe: whole lines, no \r
  // Progress and checkpoints on thread 0; the slow part (writing, printing) outside the lock.
  const auto report = [&] {
    std::optional<StudyResults> snapshot;
    std::optional<SweepProgress> progress;
    {
      std::lock_guard lock(mutex);
      const double elapsed = seconds_since(start);
      if (options.progress && seconds_since(last_progress) >= options.progress_seconds) {
        progress = SweepProgress{done, count, unstable, elapsed};
        last_progress = Clock::now();
      }
      if (options.checkpoint && seconds_since(last_checkpoint) >= options.checkpoint_seconds) {
        snapshot = results;
        last_checkpoint = Clock::now();
        if (log_lines) {
          const double rate = elapsed > 0 ? done / elapsed : 0.0;
          std::fprintf(
              stderr,
              "impactid run: checkpoint: %ld of %ld points (%.0f%%), %.1f/s on %d "
              "ranks, ETA %s, %ld not ok\n",
              done, count, count ? 100.0 * done / count : 100.0, rate, ranks_,
              rate > 0 ? (std::to_string(std::lround((count - done) / rate)) + " s").c_str() : "?",
              unstable);
        }
      }
    }
    if (snapshot) options.checkpoint(*snapshot);
    if (progress) options.progress(*progress);
  };

  const bool master_computes = ranks_ <= kMasterComputesUpToRanks;
  const auto finished = [&] {
    std::lock_guard lock(mutex);
    const bool more = !stopping() && next_window < window_count;
    return ready == ranks_ - 1 && out_total == 0 && !more;
  };
  // With rank 0 computing, `threads` more threads take windows from the queue.
  serve_and_compute(
      master_computes ? std::max(1, options.threads) : 0, handle, report, finished, [&] {
      WindowWorkspace workspace;
      for (;;) {
        long window = 0;
        {
          std::lock_guard lock(mutex);
          if (stopping() || next_window >= window_count) break;
          window = next_window++;
        }
        const long first = window * kBatchLanes;
        const auto size = static_cast<std::size_t>(std::min<long>(kBatchLanes, count - first));
        const std::span points_of_window(todo.data() + first, size);
        std::optional<std::string> failed =
            evaluate_window_checked(points, points_of_window, workspace);
        std::lock_guard lock(mutex);
        if (failed) {
          if (!error) error = "rank 0: " + *failed;
          break;
        }
        for (std::size_t k = 0; k < size; ++k) {
          store_point(results, points, points_of_window[k], workspace.simulations[k],
                      workspace.evaluations[k]);
          ++done;
          ++computed_by[0];
          if (workspace.evaluations[k].summary.status != RunStatus::ok) ++unstable;
        }
      }
      });
  for (int r = 1; r < ranks_; ++r) MPI_Send(nullptr, 0, MPI_CHAR, r, kTagEndSweep, MPI_COMM_WORLD);

  std::string shares;
  for (int r = 0; r < ranks_; ++r) {
    shares += (r ? ", " : "") + std::to_string(computed_by[static_cast<std::size_t>(r)]);
  }
  std::fprintf(stderr, "impactid run: %d ranks (rank 0 %s): points computed per rank: %s\n", ranks_,
               master_computes ? "serving and computing" : "serving", shares.c_str());
  outcome.computed = done;
  outcome.unstable = unstable;
  outcome.interrupted = done < count;
  outcome.wall_time_s = seconds_since(start);
  if (options.progress) options.progress({done, count, unstable, outcome.wall_time_s});
  if (error) {
    if (options.checkpoint) options.checkpoint(results);  // keep everything computed
    throw std::runtime_error(*error +
                             " (every point computed so far is saved; fix the cause "
                             "and continue with --resume)");
  }
  return outcome;
}

}  // namespace impactid
