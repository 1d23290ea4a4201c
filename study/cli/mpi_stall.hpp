// Rank 0's record of the work out at each worker of impactid-mpi, and its watch for a stalled
// worker (study/cli/mpi_sweep.hpp, study/cli/mpi_search.cpp).
//
// A worker that stops computing without dying (SIGSTOP, a hung node, a process swapped out)
// never answers, and MPI tells rank 0 nothing: mpirun ends the job only when a rank exits. So
// rank 0 times the work it hands out. A job (a sweep's batch, a message of searches) is
// overdue when the worker has held it, since it could start on it, longer than
// max(min_seconds, factor × expected), where expected is the job's length in units (rounds of
// one window, or one search, per worker thread) times the slowest cost per unit measured on
// any rank so far. The slowest, not the mean: the bound is to catch a worker that computes
// nothing, not a slow one, and a plan's points differ in cost by orders of magnitude (an
// unstable point stops early, a finer mesh costs n²); a job handed out twice costs a duplicate
// computation, never a different result. Before anything is measured nothing is overdue.
//
// A worker whose oldest job is overdue is stalled: every job it holds is handed to other ranks,
// and whichever answer comes first is kept (a point's numbers depend only on its index, so
// every answer is the same). A stalled worker that answers again is a worker again; its late
// answers for work already done are received and dropped.
#pragma once

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include "study/cli/mpi_protocol.hpp"

namespace impactid::mpi_protocol {

/// When a job out at a worker is handed to another rank (impactid-mpi run's --stall-factor
/// and --stall-min-seconds).
struct StallOptions {
  /// Multiple of a job's expected time (its units × the slowest cost per unit measured so far)
  /// after which it is handed to another rank; > 1.
  double factor = 10.0;
  /// Seconds a job is never handed on before, whatever its expected time; > 0. A few seconds:
  /// longer than a message's trip and a worker's scheduling hiccups on a loaded node.
  double min_seconds = 5.0;
};

class JobsOut {
 public:
  struct Job {
    long id = 0;
    double units = 1;  ///< its length: rounds of work on the worker's threads
    Clock::time_point sent;
  };
  /// A worker found stalled: its jobs (oldest first) and how long the oldest had been held.
  struct Stall {
    int worker = 0;
    std::vector<Job> jobs;
    double seconds = 0;
    double bound = 0;
  };

  /// `lost`: ranks given up on in an earlier sweep (MpiMaster), never sent work again.
  JobsOut(StallOptions options, const std::vector<char>& lost)
      : options_(options),
        lost_(lost),
        out_(lost.size()),
        last_answer_(lost.size()),
        stalled_(lost.size(), false),
        answered_plan_(lost.size(), false),
        silent_(lost.size(), false),
        plan_sent_(Clock::now()) {}

  // --- the plan's first answer (Ready, or an error) ---

  /// A worker answered the plan, now.
  void answered_plan(int worker) {
    answered_plan_[at(worker)] = true;
    slowest_plan_answer_ = std::max(slowest_plan_answer_, seconds_since(plan_sent_));
  }
  /// Whether every worker not lost answered the plan or was given up on.
  bool plan_answered() const {
    for (std::size_t w = 1; w < out_.size(); ++w) {
      if (!lost_[w] && !answered_plan_[w] && !silent_[w]) return false;
    }
    return true;
  }
  /// Called when everything else is done: the workers that have not answered the plan in
  /// max(min_seconds, factor × the slowest answer of the others) are given up on (silent), and
  /// returned with how long they were waited for. The rank 0 of a cheap plan may compute every
  /// point before the workers have parsed the plan (docs/scale.md); they are waited for, within
  /// that bound, so that no Ready of theirs arrives after the sweep.
  std::vector<std::pair<int, double>> give_up_on_plan() {
    std::vector<std::pair<int, double>> given_up;
    const double waited = seconds_since(plan_sent_);
    if (waited <= std::max(options_.min_seconds, options_.factor * slowest_plan_answer_)) {
      return given_up;
    }
    for (std::size_t w = 1; w < out_.size(); ++w) {
      if (lost_[w] || answered_plan_[w] || silent_[w]) continue;
      silent_[w] = true;
      given_up.emplace_back(static_cast<int>(w), waited);
    }
    return given_up;
  }
  /// At the end of a sweep or search: whether every worker answered the plan, after giving up
  /// on those past the bound (give_up_on_plan), each named on stderr.
  bool plan_answered_or_given_up() {
    if (plan_answered()) return true;
    for (const auto& [worker, seconds] : give_up_on_plan()) {
      std::fprintf(stderr, "impactid run: rank %d has not answered the plan in %.1f s\n", worker,
                   seconds);
    }
    return plan_answered();
  }
  /// The workers still owing an answer at the end of a sweep: stalled, or silent on the plan.
  std::vector<int> unresponsive() const {
    std::vector<int> ranks;
    for (std::size_t w = 1; w < out_.size(); ++w) {
      if (!lost_[w] && (silent_[w] || (stalled_[w] && !out_[w].empty()))) {
        ranks.push_back(static_cast<int>(w));
      }
    }
    return ranks;
  }

  // --- jobs ---

  void sent(int worker, long id, double units) {
    out_[at(worker)].push_back({id, units, Clock::now()});
  }

  std::size_t out(int worker) const { return out_[at(worker)].size(); }
  bool stalled(int worker) const { return stalled_[at(worker)]; }
  bool holds(int worker, long id) const {
    const auto& jobs = out_[at(worker)];
    return std::any_of(jobs.begin(), jobs.end(), [id](const Job& j) { return j.id == id; });
  }
  /// Jobs out at workers that are not stalled: the answers rank 0 still waits for.
  long awaited() const {
    long total = 0;
    for (std::size_t w = 0; w < out_.size(); ++w) {
      if (!stalled_[w]) total += static_cast<long>(out_[w].size());
    }
    return total;
  }
  /// The seconds the worker's oldest job has been out (0 if none).
  double oldest_seconds(int worker) const {
    const auto& jobs = out_[at(worker)];
    return jobs.empty() ? 0.0 : seconds_since(jobs.front().sent);
  }

  /// The worker's answer to its oldest job (a worker computes its jobs in the order received,
  /// and MPI keeps the order of messages between two ranks): takes that job out and measures
  /// its cost from when the worker could start it (sent, or its previous answer) to now. A
  /// stalled worker that answers is a worker again, unmeasured: its time is the stall's, and
  /// would raise every later bound. Nothing when it holds no job.
  std::optional<Job> answered(int worker) {
    const std::size_t w = at(worker);
    const auto now = Clock::now();
    if (out_[w].empty()) return std::nullopt;
    const Job job = out_[w].front();
    out_[w].pop_front();
    const double seconds =
        std::chrono::duration<double>(now - std::max(job.sent, last_answer_[w])).count();
    if (!stalled_[w]) measured(seconds, job.units);
    last_answer_[w] = now;
    stalled_[w] = false;
    return job;
  }

  /// A worker's error in place of its oldest job's answer: takes that job out, unmeasured.
  void failed(int worker) {
    const std::size_t w = at(worker);
    if (!out_[w].empty()) out_[w].pop_front();
    last_answer_[w] = Clock::now();
    stalled_[w] = false;
  }

  /// Work measured elsewhere (rank 0's own windows or searches).
  void measured(double seconds, double units) {
    if (units > 0) slowest_per_unit_ = std::max(slowest_per_unit_, seconds / units);
  }

  /// The bound on a job of `units`: max(min_seconds, factor × expected); +∞ before anything
  /// is measured.
  double bound(double units) const {
    if (slowest_per_unit_ <= 0) return std::numeric_limits<double>::infinity();
    return std::max(options_.min_seconds, options_.factor * slowest_per_unit_ * units);
  }

  /// The bound on a rank's first answer when every other answer is in: max(min_seconds,
  /// factor × the slowest first answer of the others `slowest_seconds`).
  double first_answer_bound(double slowest_seconds) const {
    return std::max(options_.min_seconds, options_.factor * slowest_seconds);
  }

  /// The workers, not stalled yet, whose oldest job is now overdue; marks them stalled.
  std::vector<Stall> find_stalled() {
    std::vector<Stall> found;
    const auto now = Clock::now();
    for (std::size_t w = 0; w < out_.size(); ++w) {
      if (stalled_[w] || out_[w].empty()) continue;
      const Job& oldest = out_[w].front();
      const double held =
          std::chrono::duration<double>(now - std::max(oldest.sent, last_answer_[w])).count();
      const double limit = bound(oldest.units);
      if (held <= limit) continue;
      stalled_[w] = true;
      found.push_back({static_cast<int>(w),
                       {out_[w].begin(), out_[w].end()},
                       std::chrono::duration<double>(now - oldest.sent).count(),
                       limit});
    }
    return found;
  }

 private:
  static std::size_t at(int worker) { return static_cast<std::size_t>(worker); }

  StallOptions options_;
  std::vector<char> lost_;
  std::vector<std::deque<Job>> out_;
  std::vector<Clock::time_point> last_answer_;
  std::vector<bool> stalled_;
  std::vector<bool> answered_plan_;
  std::vector<bool> silent_;
  Clock::time_point plan_sent_;
  double slowest_plan_answer_ = 0;
  double slowest_per_unit_ = 0;  ///< seconds per unit, the slowest measured
};

/// For rank 0's computing threads: the next task (`next()`, called with the mutex held), waiting
/// for one while the run is neither over nor stopping; nothing when it is. The wait has a
/// timeout because a stop request comes from a signal handler, which notifies nobody.
template <class Stopping, class Next>
std::optional<long> wait_for_rank0_task(std::mutex& mutex, std::condition_variable& wake,
                                        const bool& over, Stopping&& stopping, Next&& next) {
  std::unique_lock lock(mutex);
  std::optional<long> taken;
  while (!over && !stopping() && !(taken = next())) {
    wake.wait_for(lock, std::chrono::milliseconds(50));
  }
  return taken;
}

}  // namespace impactid::mpi_protocol
