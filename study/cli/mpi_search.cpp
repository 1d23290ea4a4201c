// An optimisation's searches over MPI ranks (MpiMaster::run_searches, study/cli/mpi_sweep.hpp):
// rank 0 hands whole searches out, the workers run them with run_search() and send back their
// rows; a stalled rank's searches are handed out again (study/cli/mpi_stall.hpp). A search's
// rows depend only on its index and the plan, so the table is the one a single process writes.
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
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
#include <utility>
#include <vector>

#include "study/cli/mpi_protocol.hpp"
#include "study/cli/mpi_sweep.hpp"

namespace impactid {
namespace {

using namespace mpi_protocol;

std::size_t search_row_width(const StudyResults& r) {
  return 1 + r.parameters.size() + r.indicators.size();  // status, columns
}

void pack_rows(const StudyResults& rows, std::vector<double>& out) {
  out.push_back(static_cast<double>(rows.status.size()));
  for (std::size_t k = 0; k < rows.status.size(); ++k) {
    out.push_back(rows.status[k]);
    for (const ResultColumn& c : rows.parameters) out.push_back(c.values[k]);
    for (const ResultColumn& c : rows.indicators) out.push_back(c.values[k]);
  }
}

// Reads the rows pack_rows() wrote at `at` into `rows` (empty_search_rows' columns); advances
// `at`. False if the message is shorter than it says.
bool unpack_rows(const std::vector<double>& in, std::size_t& at, StudyResults& rows) {
  if (at >= in.size()) return false;
  const auto count = static_cast<std::size_t>(in[at++]);
  const std::size_t width = search_row_width(rows);
  if (in.size() - at < count * width) return false;
  for (std::size_t k = 0; k < count; ++k) {
    rows.status.push_back(static_cast<int>(in[at++]));
    rows.dimensions[0].values.push_back(static_cast<double>(k));
    for (ResultColumn& c : rows.parameters) c.values.push_back(in[at++]);
    for (ResultColumn& c : rows.indicators) c.values.push_back(in[at++]);
  }
  return true;
}

// The test hook (tests/mpi_run_test.cpp), as IMPACTID_MPI_FAIL_AT_POINT for sweeps: the search
// whichever rank runs it fails on, or −1.
long injected_failure_search() {
  const char* text = std::getenv("IMPACTID_MPI_FAIL_AT_SEARCH");
  return text ? std::atol(text) : -1;
}

// The test hook (tests/mpi_run_test.cpp) of a worker stopped between a search's two messages:
// the rank that sends itself SIGSTOP right after its first search's rows, or −1.
int injected_stop_after_rows() {
  const char* text = std::getenv("IMPACTID_MPI_STOP_AFTER_ROWS");
  return text ? std::atoi(text) : -1;
}

SearchOutcome run_search_checked(const Plan& plan, long start, const StudyResults& previous,
                                 const std::atomic<bool>* stop) {
  static const long fail_at = injected_failure_search();
  if (start == fail_at) {
    throw std::runtime_error("failure injected by IMPACTID_MPI_FAIL_AT_SEARCH=" +
                             std::to_string(fail_at));
  }
  return run_search(plan, start, &previous, stop);
}

}  // namespace

void mpi_protocol::serve_searches(const Plan& plan, int threads,
                                  const std::vector<double>& message) {
  const std::string rank = "rank " + std::to_string(world_rank());
  std::vector<long> starts;
  std::vector<StudyResults> previous;
  for (std::size_t at = 0; at < message.size();) {
    starts.push_back(static_cast<long>(message[at++]));
    previous.push_back(empty_search_rows(plan));
    if (!unpack_rows(message, at, previous.back())) {
      send_text(rank + ": a message of searches ends early", 0, kTagError);
      return;
    }
  }
  std::vector<std::optional<SearchOutcome>> outcomes(starts.size());
  std::optional<std::string> error;
  const auto count = static_cast<long>(starts.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads))
  for (long k = 0; k < count; ++k) {
    const auto i = static_cast<std::size_t>(k);
    try {
      outcomes[i] = run_search_checked(plan, starts[i], previous[i], nullptr);
    } catch (const std::exception& e) {
#pragma omp critical(impactid_mpi_search_failure)
      if (!error) error = rank + ": search " + std::to_string(starts[i]) + ": " + e.what();
    }
  }
  if (error) {
    send_text(*error, 0, kTagError);
    return;
  }
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const SearchOutcome& o = *outcomes[i];
    std::vector<double> packed{static_cast<double>(starts[i]), static_cast<double>(o.computed),
                               static_cast<double>(o.reused), o.interrupted ? 1.0 : 0.0};
    pack_rows(o.rows, packed);
    send_rows(packed, kTagSearchRows);
    static const int stop_rank = injected_stop_after_rows();
    static bool stopped_once = false;
    if (!stopped_once && stop_rank == world_rank()) {
      stopped_once = true;
      std::raise(SIGSTOP);
    }
    send_text(o.termination, 0, kTagSearchEnd);
  }
}

void MpiMaster::run_searches(const Plan& plan, std::span<const long> starts,
                             std::span<const StudyResults> previous, const std::atomic<bool>* stop,
                             const std::function<void(long, SearchOutcome)>& done) {
  if (ranks_ == 1) {
    for (const long s : starts) {
      if (stop && stop->load()) break;
      done(s, run_search(plan, s, &previous[static_cast<std::size_t>(s)], stop));
    }
    return;
  }
  const std::string plan_message = std::filesystem::absolute(plan.path).string() + '\0' + plan.text;
  for (int r = 1; r < ranks_; ++r) {
    if (!lost_[static_cast<std::size_t>(r)]) outbox_.send_text(plan_message, r, kTagPlan);
  }

  // As in MpiMaster::run: thread 0 serves (the one thread that calls MPI), the others run
  // searches when rank 0 computes, and wait on `wake` for a stalled rank's searches once the
  // queue is empty. The mutex guards everything below it; done() is called without it.
  std::mutex mutex;
  std::condition_variable wake;
  std::vector<int> threads_of(static_cast<std::size_t>(ranks_), 0);  // 0 until Ready
  std::vector<long> ran_by(static_cast<std::size_t>(ranks_), 0);     // searches per rank
  JobsOut jobs(stall, lost_);
  std::vector<std::vector<long>> messages;  // the searches of every message out, by job id
  // Per worker: the answers still to come of the message it is answering (one per search,
  // sent together once all its searches ended).
  std::vector<long> answers_left(static_cast<std::size_t>(ranks_), 0);
  std::vector<long> message_of(static_cast<std::size_t>(ranks_), -1);
  // Per worker: the rows of its latest search, received, whose kTagSearchEnd is still to come.
  // Thread 0 only.
  std::vector<std::vector<double>> rows_in(static_cast<std::size_t>(ranks_));
  struct Orphan {
    long search = 0;
    int from = 0;  // the stalled rank
    Clock::time_point sent;
  };
  std::deque<Orphan> orphans;  // a stalled rank's searches, handed out before new ones
  // Per search: its outcome is in (the first answer wins), rank 0 took it from an orphan.
  std::vector<char> search_done(previous.size(), 0), search_taken(previous.size(), 0);
  std::size_t next = 0;
  std::size_t searches_done = 0;
  bool over = false;
  std::optional<std::string> error;
  const auto stopping = [&] { return error || (stop && stop->load()); };

  // Sends the worker, when it holds none, a message of as many searches as it has threads: a
  // stalled rank's first. Thread 0, mutex held.
  const auto give = [&](int worker) {
    const auto w = static_cast<std::size_t>(worker);
    if (stopping() || threads_of[w] == 0 || jobs.stalled(worker) || jobs.out(worker) > 0) return;
    std::vector<long> given;
    while (given.size() < static_cast<std::size_t>(threads_of[w]) && !orphans.empty()) {
      const Orphan o = orphans.front();
      orphans.pop_front();
      if (search_done[static_cast<std::size_t>(o.search)]) continue;
      given.push_back(o.search);
      std::fprintf(stderr,
                   "impactid run: search %ld, out at rank %d for %.1f s, handed again to rank %d\n",
                   o.search, o.from, seconds_since(o.sent), worker);
    }
    while (given.size() < static_cast<std::size_t>(threads_of[w]) && next < starts.size()) {
      given.push_back(starts[next++]);
    }
    if (given.empty()) return;
    std::vector<double> message;
    for (const long s : given) {
      message.push_back(static_cast<double>(s));
      pack_rows(previous[static_cast<std::size_t>(s)], message);
    }
    outbox_.send(message.data(), message.size(), MPI_DOUBLE, worker, kTagSearches);
    jobs.sent(worker, static_cast<long>(messages.size()), 1.0);  // one search per thread
    messages.push_back(std::move(given));
  };

  // Handles one message from a worker if one waits. Thread 0.
  const auto handle = [&]() -> bool {
    std::optional<Received> message = inbox_.next();
    if (!message) return false;
    const int worker = message->source;
    const auto w = static_cast<std::size_t>(worker);
    if (lost_[w]) return true;  // given up on earlier: nothing it sends belongs here
    switch (message->tag) {
      case kTagReady: {
        const int threads = message->ready_threads();
        std::lock_guard lock(mutex);
        jobs.answered_plan(worker);
        threads_of[w] = threads;
        give(worker);
        break;
      }
      case kTagSearchRows:  // kept until its kTagSearchEnd, which MPI delivers next from it
        rows_in[w] = message->values<double>();
        break;
      case kTagSearchEnd: {
        // Not a blocking probe for it after the rows: a worker stopped between its two
        // messages would hold thread 0 there, and with it the watch for stalled ranks.
        std::string termination = message->text();
        const std::vector<double> packed = std::exchange(rows_in[w], {});
        SearchOutcome outcome;
        outcome.rows = empty_search_rows(plan);
        std::size_t at = 4;
        const bool whole = packed.size() >= 4 && unpack_rows(packed, at, outcome.rows);
        std::optional<long> search;
        {
          std::lock_guard lock(mutex);
          if (answers_left[w] == 0) {  // the first answer to its oldest message
            const bool was_stalled = jobs.stalled(worker);
            if (const std::optional<JobsOut::Job> job = jobs.answered(worker)) {
              message_of[w] = job->id;
              answers_left[w] =
                  static_cast<long>(messages[static_cast<std::size_t>(job->id)].size());
              if (was_stalled) {
                std::fprintf(stderr, "impactid run: rank %d answers again (after %.1f s)\n", worker,
                             seconds_since(job->sent));
              }
            }
          }
          const std::vector<long>* asked =
              answers_left[w] > 0 ? &messages[static_cast<std::size_t>(message_of[w])] : nullptr;
          const long s = whole ? static_cast<long>(packed[0]) : -1;
          if (!whole || !asked || std::find(asked->begin(), asked->end(), s) == asked->end()) {
            if (!error) {
              error = "rank " + std::to_string(worker) +
                      (whole ? " sent a search it was not asked for"
                             : " sent a search's rows cut short");
            }
          } else if (!search_done[static_cast<std::size_t>(s)]) {
            // The first answer wins; a stalled rank's late one, or the copy handed again, is
            // dropped (the same rows).
            search_done[static_cast<std::size_t>(s)] = 1;
            ++searches_done;
            ++ran_by[w];
            search = s;
            outcome.computed = static_cast<long>(packed[1]);
            outcome.reused = static_cast<long>(packed[2]);
            outcome.interrupted = packed[3] != 0.0;
            outcome.termination = std::move(termination);
          }
          if (answers_left[w] > 0 && --answers_left[w] == 0) give(worker);
        }
        if (search) done(*search, std::move(outcome));
        break;
      }
      case kTagError: {
        std::lock_guard lock(mutex);
        if (!error) error = message->text();
        if (threads_of[w] == 0) {
          jobs.answered_plan(worker);  // it failed on the plan, before Ready
        } else {
          jobs.failed(worker);  // its whole message of searches failed
          answers_left[w] = 0;
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

  // As in MpiMaster::run: a stalled worker's searches go to the others. Thread 0.
  const auto watch_stalls = [&] {
    outbox_.collect();
    std::lock_guard lock(mutex);
    const std::vector<JobsOut::Stall> stalls = jobs.find_stalled();
    for (const JobsOut::Stall& s : stalls) {
      std::fprintf(stderr,
                   "impactid run: rank %d has not answered its searches for %.1f s (bound %.1f "
                   "s); they go to other ranks\n",
                   s.worker, s.seconds, s.bound);
      for (const JobsOut::Job& job : s.jobs) {
        for (const long search : messages[static_cast<std::size_t>(job.id)]) {
          if (!search_done[static_cast<std::size_t>(search)]) {
            orphans.push_back({search, s.worker, job.sent});
          }
        }
      }
    }
    if (stalls.empty() || orphans.empty()) return;
    for (int r = 1; r < ranks_; ++r) give(r);
    wake.notify_all();
  };

  const bool master_computes = ranks_ <= kMasterComputesUpToRanks;
  const auto finished = [&] {
    std::lock_guard lock(mutex);
    const bool more = !stopping() && searches_done < starts.size();
    if (more || jobs.awaited() > 0) return false;
    if (!jobs.plan_answered_or_given_up()) return false;
    over = true;
    wake.notify_all();
    return true;
  };
  // The next search for one of rank 0's threads: from the queue, else a stalled rank's that
  // nobody has finished or taken. Mutex held.
  const auto next_for_rank0 = [&]() -> std::optional<long> {
    if (next < starts.size()) return starts[next++];
    for (const Orphan& o : orphans) {
      const auto at = static_cast<std::size_t>(o.search);
      if (search_done[at] || search_taken[at]) continue;
      search_taken[at] = 1;
      std::fprintf(stderr,
                   "impactid run: search %ld, out at rank %d for %.1f s, taken again by rank 0\n",
                   o.search, o.from, seconds_since(o.sent));
      return o.search;
    }
    return std::nullopt;
  };
  // Progress and checkpoints come with done(), from the Optimization (study/studies/optimizer.cpp).
  serve_and_compute(master_computes ? std::max(1, omp_get_max_threads()) : 0, handle, watch_stalls,
                    finished, [&] {
                      for (;;) {
                        const std::optional<long> taken =
                            wait_for_rank0_task(mutex, wake, over, stopping, next_for_rank0);
                        if (!taken) break;
                        const long s = *taken;
                        const auto computing_since = Clock::now();
                        std::optional<SearchOutcome> outcome;
                        try {
                          outcome = run_search_checked(plan, s,
                                                       previous[static_cast<std::size_t>(s)], stop);
                        } catch (const std::exception& e) {
                          std::lock_guard lock(mutex);
                          if (!error)
                            error = "rank 0: search " + std::to_string(s) + ": " + e.what();
                          break;
                        }
                        bool first = false;
                        {
                          std::lock_guard lock(mutex);
                          jobs.measured(seconds_since(computing_since), 1.0);
                          first = !search_done[static_cast<std::size_t>(s)];
                          if (first) {
                            search_done[static_cast<std::size_t>(s)] = 1;
                            ++searches_done;
                            ++ran_by[0];
                          }
                        }
                        if (first) done(s, std::move(*outcome));
                      }
                    });
  give_up_on(jobs.unresponsive(), "searches");
  for (int r = 1; r < ranks_; ++r) {
    if (!lost_[static_cast<std::size_t>(r)]) {
      MPI_Send(nullptr, 0, MPI_CHAR, r, kTagEndSweep, MPI_COMM_WORLD);
    }
  }

  std::string shares;
  for (int r = 0; r < ranks_; ++r) {
    shares += (r ? ", " : "") + std::to_string(ran_by[static_cast<std::size_t>(r)]);
  }
  std::fprintf(stderr, "impactid run: %d ranks (rank 0 %s): searches run per rank: %s\n", ranks_,
               master_computes ? "serving and computing" : "serving", shares.c_str());
  if (error) throw std::runtime_error(*error);
}

}  // namespace impactid
