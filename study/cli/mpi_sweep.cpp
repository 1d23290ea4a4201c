#include "study/cli/mpi_sweep.hpp"

#include <mpi.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
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

// The test hook of mpi_protocol::send_rows: the rank that stops in its first rows message, or −1.
int injected_stop_in_rows() {
  const char* text = std::getenv("IMPACTID_MPI_STOP_IN_ROWS");
  return text ? std::atoi(text) : -1;
}

}  // namespace

void mpi_protocol::send_rows(const std::vector<double>& packed, int tag) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Isend(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, 0, tag, MPI_COMM_WORLD,
            &request);
  static const int stop_rank = injected_stop_in_rows();
  static bool stopped_once = false;
  if (!stopped_once && stop_rank == world_rank()) {
    stopped_once = true;
    std::raise(SIGSTOP);
  }
  MPI_Wait(&request, MPI_STATUS_IGNORE);
}

namespace {

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

void send_batch_rows(const WorkerPlan& w, const std::vector<long>& indices) {
  const StudyResults& r = w.rows;
  std::vector<double> packed;
  packed.reserve(indices.size() * row_width(r));
  for (std::size_t k = 0; k < indices.size(); ++k) {
    packed.push_back(static_cast<double>(indices[k]));
    packed.push_back(r.status[k]);
    for (const ResultColumn& c : r.parameters) packed.push_back(c.values[k]);
    for (const ResultColumn& c : r.indicators) packed.push_back(c.values[k]);
  }
  send_rows(packed, kTagResult);
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
          send_batch_rows(*served, indices);
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
        MPI_Send(nullptr, 0, MPI_CHAR, 0, kTagStopped, MPI_COMM_WORLD);
        MPI_Recv(nullptr, 0, MPI_CHAR, 0, kTagFinalize, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
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
  lost_.assign(static_cast<std::size_t>(ranks_), 0);
}

void MpiMaster::give_up_on(const std::vector<int>& ranks, const char* what) {
  for (const int r : ranks) {
    lost_[static_cast<std::size_t>(r)] = 1;
    std::fprintf(stderr,
                 "impactid run: rank %d still has not answered at the end of the %s; it gets no "
                 "more work, and the job ends without it\n",
                 r, what);
  }
}

std::vector<int> MpiMaster::release_workers() {
  std::vector<char> answered(lost_);  // a rank given up on is not waited for
  for (int r = 1; r < ranks_; ++r) {
    if (!lost_[static_cast<std::size_t>(r)]) {
      MPI_Send(nullptr, 0, MPI_CHAR, r, kTagStop, MPI_COMM_WORLD);
    }
  }
  const auto start = Clock::now();
  const auto waiting = [&] {
    return std::any_of(answered.begin() + 1, answered.end(), [](char a) { return !a; });
  };
  while (waiting() && seconds_since(start) < stall.min_seconds) {
    outbox_.collect();
    if (const std::optional<Received> message = inbox_.next()) {
      // Anything else is a late answer of a rank given up on: dropped.
      if (message->tag == kTagStopped) answered[static_cast<std::size_t>(message->source)] = 1;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  std::vector<int> silent;
  for (int r = 1; r < ranks_; ++r) {
    if (lost_[static_cast<std::size_t>(r)] || !answered[static_cast<std::size_t>(r)]) {
      silent.push_back(r);
    }
  }
  if (silent.empty()) {
    for (int r = 1; r < ranks_; ++r)
      MPI_Send(nullptr, 0, MPI_CHAR, r, kTagFinalize, MPI_COMM_WORLD);
  }
  return silent;
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
  for (int r = 1; r < ranks_; ++r) {
    if (!lost_[static_cast<std::size_t>(r)]) outbox_.send_text(plan_message, r, kTagPlan);
  }

  // Shared by rank 0's threads: thread 0 serves the workers (the only thread that calls MPI,
  // as MPI_THREAD_FUNNELED asks), the others compute windows when rank 0 computes. The mutex
  // guards `results` and everything below it.
  std::mutex mutex;
  // Rank 0's computing threads wait on it when the queue is empty: a stalled rank's batch may
  // still come back to them (`orphans`).
  std::condition_variable wake;
  std::vector<int> threads_of(static_cast<std::size_t>(ranks_), 0);      // 0 until Ready
  std::vector<long> batch_windows(static_cast<std::size_t>(ranks_), 0);  // its batch size now
  std::vector<long> computed_by(static_cast<std::size_t>(ranks_), 0);    // points per rank
  JobsOut jobs(stall, lost_);
  struct Batch {
    long first_window = 0, end_window = 0;
  };
  std::vector<Batch> batches;  // every batch handed out, by id (JobsOut's job id)
  // Batches of stalled ranks, to hand out again before new ones: held up, they hold up the
  // checkpoints and the end of the run.
  struct Orphan {
    long batch = 0;
    int from = 0;  // the stalled rank
    Clock::time_point sent;
    bool taken_by_rank0 = false;  // some of its windows, and said so
  };
  std::deque<Orphan> orphans;
  // Per window: its rows are stored (the first answer wins), rank 0 took it from an orphan.
  std::vector<char> window_done(static_cast<std::size_t>(window_count), 0);
  std::vector<char> window_taken(static_cast<std::size_t>(window_count), 0);
  long next_window = 0, done = 0, unstable = 0;
  bool over = false;  // thread 0 is done serving: rank 0's computing threads end
  std::optional<std::string> error;
  const auto stopping = [&] { return error || (options.stop && options.stop->load()); };
  const auto batch_done = [&](long id) {
    const Batch& b = batches[static_cast<std::size_t>(id)];
    return std::all_of(window_done.begin() + b.first_window, window_done.begin() + b.end_window,
                       [](char d) { return d != 0; });
  };
  const auto first_point = [&](long window) { return window * kBatchLanes; };
  const auto end_point = [&](long window) { return std::min(count, window * kBatchLanes); };

  // Sends the worker batches until it holds two: a stalled rank's first, then new ones. Thread
  // 0, mutex held. Near the end new batches shrink (a share of what is left, but at least a
  // window per thread), so that no worker gets a large last batch while the others wait.
  const auto give = [&](int worker) {
    const auto w = static_cast<std::size_t>(worker);
    while (!stopping() && threads_of[w] > 0 && !jobs.stalled(worker) && jobs.out(worker) < 2) {
      std::optional<long> id;
      while (!id && !orphans.empty()) {
        const Orphan o = orphans.front();
        orphans.pop_front();
        if (batch_done(o.batch) || jobs.holds(worker, o.batch)) continue;
        id = o.batch;
        const Batch& b = batches[static_cast<std::size_t>(o.batch)];
        std::fprintf(stderr,
                     "impactid run: batch %ld (%ld points), out at rank %d for %.1f s, handed "
                     "again to rank %d\n",
                     o.batch, end_point(b.end_window) - first_point(b.first_window), o.from,
                     seconds_since(o.sent), worker);
      }
      if (!id) {
        if (next_window >= window_count) return;
        const long left = window_count - next_window;
        const long windows =
            std::min({batch_windows[w], left, std::max<long>(threads_of[w], left / (2L * ranks_))});
        id = static_cast<long>(batches.size());
        batches.push_back({next_window, next_window + windows});
        next_window += windows;
      }
      const Batch& b = batches[static_cast<std::size_t>(*id)];
      const long first = first_point(b.first_window);
      const long last = end_point(b.end_window);
      outbox_.send(todo.data() + first, static_cast<std::size_t>(last - first), MPI_LONG, worker,
                   kTagWork);
      // Its length in rounds of one window per thread: what its expected time scales with.
      const long windows = b.end_window - b.first_window;
      jobs.sent(worker, *id, static_cast<double>((windows + threads_of[w] - 1) / threads_of[w]));
    }
  };

  // Handles one message from a worker if one waits. Thread 0.
  const auto handle = [&]() -> bool {
    const std::optional<Received> message = inbox_.next();
    if (!message) return false;
    const int worker = message->source;
    const auto w = static_cast<std::size_t>(worker);
    // Given up on in an earlier sweep: nothing it sends belongs to this one.
    if (lost_[w]) return true;
    switch (message->tag) {
      case kTagReady: {
        const int threads = message->ready_threads();
        std::lock_guard lock(mutex);
        jobs.answered_plan(worker);
        threads_of[w] = threads;
        batch_windows[w] = threads_of[w];
        give(worker);  // two batches: it computes the second while rank 0 answers the first
        break;
      }
      case kTagResult: {
        const std::vector<double> packed = message->values<double>();
        std::lock_guard lock(mutex);
        const bool was_stalled = jobs.stalled(worker);
        const std::optional<JobsOut::Job> job = jobs.answered(worker);
        if (!job) {
          if (!error) error = "rank " + std::to_string(worker) + " sent rows it was not asked for";
          break;
        }
        const Batch& b = batches[static_cast<std::size_t>(job->id)];
        const long first = first_point(b.first_window);
        const long last = end_point(b.end_window);
        if (packed.size() != static_cast<std::size_t>(last - first) * width ||
            static_cast<long>(packed[0]) != todo[static_cast<std::size_t>(first)]) {
          if (!error) {
            error = "rank " + std::to_string(worker) + " sent rows of another batch or width (" +
                    std::to_string(packed.size()) + " values for " + std::to_string(last - first) +
                    " rows of " + std::to_string(width) + ")";
          }
          break;
        }
        if (was_stalled) {
          std::fprintf(stderr, "impactid run: rank %d answers again (batch %ld, after %.1f s)\n",
                       worker, job->id, seconds_since(job->sent));
        }
        // The first answer wins; a window already stored (a stalled rank's late answer, or the
        // copy handed again) is dropped. Both are the same numbers.
        for (long v = b.first_window; v < b.end_window; ++v) {
          if (window_done[static_cast<std::size_t>(v)]) continue;
          window_done[static_cast<std::size_t>(v)] = 1;
          for (long p = first_point(v); p < end_point(v + 1); ++p) {
            const std::size_t at = static_cast<std::size_t>(p - first) * width;
            const auto i = static_cast<std::size_t>(packed[at]);
            results.status[i] = static_cast<int>(packed[at + 1]);
            std::size_t c = at + 2;
            for (ResultColumn& column : results.parameters) column.values[i] = packed[c++];
            for (ResultColumn& column : results.indicators) column.values[i] = packed[c++];
            ++done;
            ++computed_by[w];
            if (results.status[i] != 0) ++unstable;
          }
        }
        // Cheap points: double the batch until a batch's round trip (its own time plus the
        // wait behind the one before it) reaches kBatchRoundTripSeconds.
        if (seconds_since(job->sent) < kBatchRoundTripSeconds &&
            batch_windows[w] < kMaxBatchWindows) {
          batch_windows[w] *= 2;
        }
        give(worker);
        break;
      }
      case kTagError: {
        std::lock_guard lock(mutex);
        if (!error) error = message->text();
        if (threads_of[w] == 0) {
          jobs.answered_plan(worker);  // it failed on the plan, before Ready
        } else {
          jobs.failed(worker);
        }
        break;
      }
      default: {
        std::lock_guard lock(mutex);
        if (!error) error = message->unexpected();
      }
    }
    return true;
  };

  // A worker whose oldest batch is overdue (study/cli/mpi_stall.hpp): its batches go to the
  // others, rank 0's computing threads included. Thread 0, mutex held.
  const auto watch_stalls = [&] {
    const std::vector<JobsOut::Stall> stalls = jobs.find_stalled();
    for (const JobsOut::Stall& s : stalls) {
      std::fprintf(stderr,
                   "impactid run: rank %d has not answered batch %ld for %.1f s (bound %.1f s); "
                   "its %zu batch(es) out go to other ranks\n",
                   s.worker, s.jobs.front().id, s.seconds, s.bound, s.jobs.size());
      for (const JobsOut::Job& job : s.jobs) {
        if (!batch_done(job.id)) orphans.push_back({job.id, s.worker, job.sent});
      }
    }
    if (stalls.empty() || orphans.empty()) return;
    for (int r = 1; r < ranks_; ++r) give(r);
    wake.notify_all();
  };

  auto last_checkpoint = Clock::now(), last_progress = Clock::now();
  const bool log_lines = !isatty(2);  // mpirun's stderr is a pipe: whole lines, no \r
  // Progress and checkpoints on thread 0; the slow part (writing, printing) outside the lock.
  const auto report = [&] {
    std::optional<StudyResults> snapshot;
    std::optional<SweepProgress> progress;
    outbox_.collect();
    {
      std::lock_guard lock(mutex);
      watch_stalls();
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
  // Over when every point is stored (or, on a stop or an error, nothing more is handed out) and
  // every worker that still answers has answered: a stalled one is not waited for.
  const auto finished = [&] {
    std::lock_guard lock(mutex);
    const bool more = !stopping() && done < count;
    if (more || jobs.awaited() > 0) return false;
    if (!jobs.plan_answered_or_given_up()) return false;
    over = true;
    wake.notify_all();
    return true;
  };
  // The next window for one of rank 0's computing threads: from the queue, else a window of a
  // stalled rank's batch that nobody has stored or taken yet. Mutex held.
  const auto next_for_rank0 = [&]() -> std::optional<long> {
    if (next_window < window_count) return next_window++;
    for (Orphan& o : orphans) {
      const Batch& b = batches[static_cast<std::size_t>(o.batch)];
      for (long v = b.first_window; v < b.end_window; ++v) {
        const auto at = static_cast<std::size_t>(v);
        if (window_done[at] || window_taken[at]) continue;
        window_taken[at] = 1;
        if (!o.taken_by_rank0) {
          o.taken_by_rank0 = true;
          std::fprintf(stderr,
                       "impactid run: batch %ld (%ld points), out at rank %d for %.1f s, taken "
                       "again by rank 0's threads\n",
                       o.batch, end_point(b.end_window) - first_point(b.first_window), o.from,
                       seconds_since(o.sent));
        }
        return v;
      }
    }
    return std::nullopt;
  };
  // With rank 0 computing, `threads` more threads take windows from the queue.
  serve_and_compute(master_computes ? std::max(1, options.threads) : 0, handle, report, finished,
                    [&] {
                      WindowWorkspace workspace;
                      for (;;) {
                        const std::optional<long> next =
                            wait_for_rank0_task(mutex, wake, over, stopping, next_for_rank0);
                        if (!next) break;
                        const long window = *next;
                        const auto computing_since = Clock::now();
                        const long first = first_point(window);
                        const auto size = static_cast<std::size_t>(end_point(window + 1) - first);
                        const std::span points_of_window(todo.data() + first, size);
                        std::optional<std::string> failed =
                            evaluate_window_checked(points, points_of_window, workspace);
                        std::lock_guard lock(mutex);
                        if (failed) {
                          if (!error) error = "rank 0: " + *failed;
                          break;
                        }
                        jobs.measured(seconds_since(computing_since), 1.0);
                        if (window_done[static_cast<std::size_t>(window)])
                          continue;  // a worker's came first
                        window_done[static_cast<std::size_t>(window)] = 1;
                        for (std::size_t k = 0; k < size; ++k) {
                          store_point(results, points, points_of_window[k],
                                      workspace.simulations[k], workspace.evaluations[k]);
                          ++done;
                          ++computed_by[0];
                          if (workspace.evaluations[k].summary.status != RunStatus::ok) ++unstable;
                        }
                      }
                    });
  give_up_on(jobs.unresponsive(), "sweep");
  for (int r = 1; r < ranks_; ++r) {
    if (!lost_[static_cast<std::size_t>(r)]) {
      MPI_Send(nullptr, 0, MPI_CHAR, r, kTagEndSweep, MPI_COMM_WORLD);
    }
  }

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
