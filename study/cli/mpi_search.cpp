// An optimisation's searches over MPI ranks (MpiMaster::run_searches, study/cli/mpi_sweep.hpp):
// rank 0 hands whole searches out, the workers run them with run_search() and send back their
// rows. A search's rows depend only on its index and the plan, so the table is the one a single
// process writes.
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
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
    MPI_Send(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, 0, kTagSearchRows,
             MPI_COMM_WORLD);
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
  for (int r = 1; r < ranks_; ++r) send_text(plan_message, r, kTagPlan);

  // As in MpiMaster::run: thread 0 serves (the one thread that calls MPI), the others run
  // searches when rank 0 computes. The mutex guards everything below it; done() is called
  // without it.
  std::mutex mutex;
  std::vector<int> threads_of(static_cast<std::size_t>(ranks_), 0);  // 0 until Ready
  std::vector<long> out(static_cast<std::size_t>(ranks_), 0);        // searches out per worker
  std::vector<long> ran_by(static_cast<std::size_t>(ranks_), 0);     // searches per rank
  std::size_t next = 0;
  long out_total = 0;
  int ready = 0;
  std::optional<std::string> error;
  const auto stopping = [&] { return error || (stop && stop->load()); };

  // Sends the worker as many searches as it has threads. Thread 0, mutex held.
  const auto give = [&](int worker) {
    const auto w = static_cast<std::size_t>(worker);
    std::vector<double> message;
    long given = 0;
    for (; given < threads_of[w] && next < starts.size() && !stopping(); ++given, ++next) {
      const long s = starts[next];
      message.push_back(static_cast<double>(s));
      pack_rows(previous[static_cast<std::size_t>(s)], message);
    }
    if (given == 0) return;
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_DOUBLE, worker, kTagSearches,
             MPI_COMM_WORLD);
    out[w] += given;
    out_total += given;
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
        ++ready;
        give(worker);
        break;
      }
      case kTagSearchRows: {
        const std::vector<double> packed = receive_array<double>(probed, MPI_DOUBLE);
        MPI_Status end;
        MPI_Probe(worker, kTagSearchEnd, MPI_COMM_WORLD, &end);
        std::string termination = receive_text(end);
        SearchOutcome outcome;
        outcome.rows = empty_search_rows(plan);
        std::size_t at = 4;
        const bool whole = packed.size() >= 4 && unpack_rows(packed, at, outcome.rows);
        std::optional<long> search;
        if (whole) {
          search = static_cast<long>(packed[0]);
          outcome.computed = static_cast<long>(packed[1]);
          outcome.reused = static_cast<long>(packed[2]);
          outcome.interrupted = packed[3] != 0.0;
          outcome.termination = std::move(termination);
        }
        {
          std::lock_guard lock(mutex);
          if (!whole && !error) {
            error = "rank " + std::to_string(worker) + " sent a search's rows cut short";
          }
          if (out[w] > 0) --out[w], --out_total;
          if (whole) ++ran_by[w];
          if (out[w] == 0) give(worker);
        }
        if (search) done(*search, std::move(outcome));
        break;
      }
      case kTagError: {
        const std::string message = receive_text(probed);
        std::lock_guard lock(mutex);
        if (!error) error = message;
        if (threads_of[w] == 0) {
          ++ready;  // it failed on the plan, before Ready
        } else {
          out_total -= out[w];  // its whole message of searches failed
          out[w] = 0;
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

  const bool master_computes = ranks_ <= kMasterComputesUpToRanks;
  const auto finished = [&] {
    std::lock_guard lock(mutex);
    const bool more = !stopping() && next < starts.size();
    return ready == ranks_ - 1 && out_total == 0 && !more;
  };
  // Progress and checkpoints come with done(), from the Optimization (optimizer.cpp).
  serve_and_compute(
      master_computes ? std::max(1, omp_get_max_threads()) : 0, handle, [] {}, finished, [&] {
      for (;;) {
        long s = 0;
        {
          std::lock_guard lock(mutex);
          if (stopping() || next >= starts.size()) break;
          s = starts[next++];
        }
        std::optional<SearchOutcome> outcome;
        try {
          outcome = run_search_checked(plan, s, previous[static_cast<std::size_t>(s)], stop);
        } catch (const std::exception& e) {
          std::lock_guard lock(mutex);
          if (!error) error = "rank 0: search " + std::to_string(s) + ": " + e.what();
          break;
        }
        {
          std::lock_guard lock(mutex);
          ++ran_by[0];
        }
        done(s, std::move(*outcome));
      }
      });
  for (int r = 1; r < ranks_; ++r) MPI_Send(nullptr, 0, MPI_CHAR, r, kTagEndSweep, MPI_COMM_WORLD);

  std::string shares;
  for (int r = 0; r < ranks_; ++r) {
    shares += (r ? ", " : "") + std::to_string(ran_by[static_cast<std::size_t>(r)]);
  }
  std::fprintf(stderr, "impactid run: %d ranks (rank 0 %s): searches run per rank: %s\n", ranks_,
               master_computes ? "serving and computing" : "serving", shares.c_str());
  if (error) throw std::runtime_error(*error);
}

}  // namespace impactid
