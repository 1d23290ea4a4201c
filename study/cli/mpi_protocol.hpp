// The messages between rank 0 and the workers of impactid-mpi (study/cli/mpi_sweep.hpp), and
// the small helpers both sides use to send and receive them.
#pragma once

#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <deque>
#include <iterator>
#include <list>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "study/plan/plan.hpp"

namespace impactid::mpi_protocol {

// Message tags. Every message is between rank 0 and one worker; MPI keeps the order of the
// messages between two ranks, which the protocol relies on (a batch before the end of its sweep,
// a search's rows before its termination).
enum Tag : int {
  kTagPlan = 1,      ///< 0 → worker: the plan file's path, '\0', the plan text
  kTagReady = 2,     ///< worker → 0: int, its OpenMP threads (batch size in windows)
  kTagWork = 3,      ///< 0 → worker: long[], flat indices of a batch
  kTagResult = 4,    ///< worker → 0: double[], per point: index, status, every column
  kTagError = 5,     ///< worker → 0: char[], "point I: message" or the plan's error
  kTagEndSweep = 6,  ///< 0 → worker: no more work of this plan
  kTagStop = 7,      ///< 0 → worker: end the program
  /// 0 → worker: double[], searches of an optimisation to run: per search its index, the
  /// number of its previous rows, then those rows (status, every column)
  kTagSearches = 8,
  /// worker → 0: double[], a finished search: index, computed, reused, interrupted, the number
  /// of rows, the rows; followed by kTagSearchEnd
  kTagSearchRows = 9,
  kTagSearchEnd = 10,  ///< worker → 0: char[], that search's termination
  /// worker → 0: nothing, the answer to kTagStop. Rank 0 waits for it, within a bound, so that
  /// a rank that stopped answering is found before MPI_Finalize, which would wait for it forever
  /// (study/cli/main_mpi.cpp).
  kTagStopped = 11,
  /// 0 → worker: nothing; every worker answered kTagStop, so MPI_Finalize (a collective over
  /// every rank) will end. A worker waits for it before MPI_Finalize, so that when a rank is
  /// silent and rank 0 calls MPI_Abort instead, no rank is inside MPI_Finalize's collective as
  /// mpirun kills them (docs/scale.md: Debian 12's mpirun teardown after an abort).
  kTagFinalize = 12,
};

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

inline int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

inline void send_text(const std::string& text, int destination, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, destination, tag, MPI_COMM_WORLD);
}

inline std::string receive_text(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return text;
}

template <class T>
std::vector<T> receive_array(const MPI_Status& probed, MPI_Datatype type) {
  int count = 0;
  MPI_Get_count(&probed, type, &count);
  std::vector<T> values(static_cast<std::size_t>(count));
  MPI_Recv(values.data(), count, type, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return values;
}

/// Rank 0's messages to the workers, sent without blocking. A message larger than MPI's eager
/// limit (OpenMPI: 4 KB between the ranks of a node) is delivered only once its receiver asks
/// for it, and a worker that is itself sending rank 0 its rows, or that is stalled, does not:
/// rank 0 would wait in MPI_Send forever and serve no one. Seen with 8b1d763 on 50 625 cheap
/// points over 3 ranks (batches grown to hundreds of windows): rank 0 and a worker each blocked
/// in MPI_Send to the other. Each message keeps its own copy of the data until MPI is done with
/// it; the copies of messages to a rank given up on live as long as the program.
class Outbox {
 public:
  Outbox() = default;
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;

  template <class T>
  void send(const T* data, std::size_t count, MPI_Datatype type, int destination, int tag) {
    Pending& p = pending_.emplace_back();
    p.bytes.assign(reinterpret_cast<const char*>(data),
                   reinterpret_cast<const char*>(data + count));
    MPI_Isend(p.bytes.data(), static_cast<int>(count), type, destination, tag, MPI_COMM_WORLD,
              &p.request);
  }
  void send_text(const std::string& text, int destination, int tag) {
    send(text.data(), text.size(), MPI_CHAR, destination, tag);
  }

  /// Forgets the messages MPI is done with (and lets MPI progress the others). Thread 0.
  void collect() {
    for (auto p = pending_.begin(); p != pending_.end();) {
      int sent = 0;
      MPI_Test(&p->request, &sent, MPI_STATUS_IGNORE);
      p = sent ? pending_.erase(p) : std::next(p);
    }
  }

 private:
  struct Pending {
    MPI_Request request = MPI_REQUEST_NULL;
    std::vector<char> bytes;
  };
  std::list<Pending> pending_;  // a list: a request's address stays put while MPI holds it
};

/// A worker's message to rank 0, received whole (Inbox).
struct Received {
  int source = 0;
  int tag = 0;
  std::vector<char> bytes;

  template <class T>
  std::vector<T> values() const {
    std::vector<T> v(bytes.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
    return v;
  }
  std::string text() const { return {bytes.begin(), bytes.end()}; }
  /// A kTagReady's OpenMP threads, at least 1.
  int ready_threads() const {
    const std::vector<int> v = values<int>();
    return v.empty() ? 1 : std::max(1, v.front());
  }
  /// The error a message of a tag rank 0 does not expect makes.
  std::string unexpected() const {
    return "rank " + std::to_string(source) + " sent an unexpected message (tag " +
           std::to_string(tag) + ")";
  }
};

/// Rank 0's receiving side: every message of the workers is received without blocking. A
/// message larger than MPI's eager limit is matched by a probe as soon as its first part is in,
/// but its rest comes only while its sender runs (OpenMPI's shared-memory transport without
/// single-copy support, as in a container without ptrace rights; TCP between nodes): a blocking
/// receive of the rows of a worker stopped in mid-send held thread 0, and with it the watch for
/// stalled ranks, forever (a CI run of 721771e, reproduced with IMPACTID_MPI_STOP_IN_ROWS). So
/// a matched message is received with MPI_Imrecv and handed out once whole, each worker's in
/// the order it sent them; one that never completes holds up only its sender's later messages.
/// Thread 0 only (MPI_THREAD_FUNNELED).
class Inbox {
 public:
  /// The next message received whole, if any: workers in turn, each one's messages in order.
  std::optional<Received> next() {
    start_arrived();
    const std::size_t n = from_.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t source = (turn_ + k) % n;
      std::deque<Pending>& queue = from_[source];
      if (queue.empty()) continue;
      int whole = 0;
      MPI_Test(&queue.front().request, &whole, MPI_STATUS_IGNORE);
      if (!whole) continue;
      Received r{static_cast<int>(source), queue.front().tag, std::move(queue.front().bytes)};
      queue.pop_front();
      turn_ = (source + 1) % n;
      return r;
    }
    return std::nullopt;
  }

 private:
  struct Pending {
    int tag = 0;
    MPI_Request request = MPI_REQUEST_NULL;
    std::vector<char> bytes;  // MPI writes here: its heap block stays put when Pending moves
  };

  // Starts the receive of every message that has arrived (its first part at least).
  void start_arrived() {
    for (;;) {
      int arrived = 0;
      MPI_Message message = MPI_MESSAGE_NULL;
      MPI_Status status;
      MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &message, &status);
      if (!arrived) return;
      int count = 0;
      MPI_Get_count(&status, MPI_BYTE, &count);
      const auto source = static_cast<std::size_t>(status.MPI_SOURCE);
      if (source >= from_.size()) from_.resize(source + 1);
      Pending& p = from_[source].emplace_back();
      p.tag = status.MPI_TAG;
      p.bytes.resize(static_cast<std::size_t>(std::max(count, 0)));
      MPI_Imrecv(p.bytes.data(), count, MPI_BYTE, &message, &p.request);
    }
  }

  std::vector<std::deque<Pending>> from_;  // by source rank
  std::size_t turn_ = 0;                   // the source looked at first next time
};

/// Rank 0's threads while it hands out work. Thread 0 serves: `handle()` takes one waiting
/// message (false when none waits), `finished()` says when the work is over, and `between()`
/// runs after each round of messages (progress, checkpoints, the watch for stalled workers); it
/// sleeps when a round found nothing. It is the only thread that calls MPI
/// (MPI_THREAD_FUNNELED). With `computing` > 0 that many more threads run `compute()`, which
/// returns when nothing is left.
///
/// Why a poll (Inbox::next) and a sleep rather than a blocking wait: rank 0 must also keep time
/// (checkpoints, progress, a worker that stops answering) and see a stop request, and MPI has no
/// receive with a timeout (MPI_Waitany and MPI_Probe wait forever). OpenMPI's blocking calls
/// spin in its progress loop anyway, so blocking would burn a core as well. The sleep starts at
/// 200 µs, so that an answer during a busy sweep waits little, and doubles while nothing comes,
/// up to 5 ms, so that a long wait (expensive points, a stalled worker) costs rank 0 about 200
/// wake-ups a second and little CPU.
template <class Handle, class Between, class Finished, class Compute>
void serve_and_compute(int computing, Handle handle, Between between, Finished finished,
                       Compute compute) {
#pragma omp parallel num_threads(1 + std::max(0, computing))
  {
    if (omp_get_thread_num() == 0) {
      constexpr std::chrono::microseconds kShortestSleep{200}, kLongestSleep{5000};
      std::chrono::microseconds sleep = kShortestSleep;
      for (;;) {
        bool busy = false;
        while (handle()) busy = true;
        between();
        if (finished()) break;
        if (busy) {
          sleep = kShortestSleep;
        } else {
          std::this_thread::sleep_for(sleep);
          sleep = std::min(2 * sleep, kLongestSleep);
        }
      }
    } else {
      compute();
    }
  }
}

/// A worker's rows (kTagResult, kTagSearchRows) to rank 0. For tests,
/// IMPACTID_MPI_STOP_IN_ROWS=R makes rank R stop itself (SIGSTOP), once, with its first rows
/// message under way: sent, not yet delivered (study/cli/mpi_sweep.cpp).
void send_rows(const std::vector<double>& packed, int tag);

/// A worker's answer to kTagSearches: runs the searches on its threads, then sends each one's
/// kTagSearchRows and kTagSearchEnd, or kTagError (study/cli/mpi_search.cpp).
void serve_searches(const Plan& plan, int threads, const std::vector<double>& message);

}  // namespace impactid::mpi_protocol
