// `mpirun -np N impactid-mpi run PLAN` (study/cli/mpi_sweep.hpp) on this machine's cores: the file
// equals a single process's bit for bit (scripts/compare-results) on 1, 2 and 3 ranks and
// other thread counts; after SIGKILL of a worker or of rank 0, --resume computes only what is
// missing and ends with the same file; an error on a worker names the point and keeps what was
// computed; shards run over MPI merge to the same file; SIGUSR1 to mpirun stops the job with
// everything computed saved; a stopped (SIGSTOP) worker's batches go to the other ranks and the
// run ends with the same file; an optimisation's searches, spread over the ranks, give the same
// file too. Registered only when impactid-mpi is built (tests/CMakeLists.txt says so otherwise).
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"
#include "study/io/results_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("mpi_run_test", name);
}

// mpirun as root in CI, more ranks than cores here.
const std::string kMpirun = std::string(IMPACTID_MPIEXEC) + " --oversubscribe --allow-run-as-root";

testing::CommandOutput shell(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen((command + " 2>&1").c_str(), "r"), pclose);
  std::string text;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe.get())) text += buffer;
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

// No job here takes a minute; this bound ends a hung one (with its ranks) so that the test fails
// by name within ctest's own bound (tests/CMakeLists.txt).
constexpr double kJobSeconds = 150;

testing::CommandOutput mpi_run(int ranks, const std::string& arguments,
                               const std::string& environment = "") {
  // timeout(1) runs mpirun in a process group of its own and signals the whole group: SIGTERM,
  // then SIGKILL 5 s later, so that no rank outlives it and keeps the output pipe open. In a
  // background group mpirun must not read the terminal: stdin is /dev/null.
  return shell("timeout -k 5 " + std::to_string(static_cast<int>(kJobSeconds)) + " " + kMpirun +
               " -np " + std::to_string(ranks) + " " + environment + " " + IMPACTID_MPI_EXECUTABLE +
               " " + arguments + " </dev/null");
}

testing::CommandOutput compare(const fs::path& expected, const fs::path& actual) {
  return shell("/usr/bin/python3 " IMPACTID_SOURCE_DIR "/scripts/compare-results " +
               expected.string() + " " + actual.string());
}

// 441 HHT points on a 500-element rod with a practical range: about a second on one
// core, long enough to kill a job between checkpoints (every 0.05 s).
const char* kPlan = R"(
[scene]
elements = 500
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 20 }
delta = { from = 0.0, to = 1.0, partitions = 20 }
[study.practical]
eps_p = 0.05
[output]
checkpoint_seconds = 0.05
)";
constexpr long kPoints = 441;

struct Study {
  fs::path plan, single;
};

// The plan and its single-process run (impactid, 2 threads), once for the whole suite.
const Study& study() {
  static const Study s = [] {
    Study s;
    s.plan = testing::write_file(scratch("grid.toml"), kPlan);
    s.single = scratch("single.h5");
    const auto o = testing::run_impactid("run " + s.plan.string() + " --threads 2 --output " +
                                         s.single.string());
    EXPECT_EQ(o.status, 0) << o.text;
    return s;
  }();
  return s;
}

TEST(MpiRun, TheFileIsTheSingleProcessOnesOnOneTwoOrThreeRanks) {
  const Study& s = study();
  struct Case {
    int ranks;
    const char* environment;  // mpirun -x: each rank's OpenMP threads
  };
  for (const Case c : {Case{1, ""}, Case{2, "-x OMP_NUM_THREADS=1"},
                       Case{2, "-x OMP_NUM_THREADS=2"}, Case{3, "-x OMP_NUM_THREADS=1"}}) {
    SCOPED_TRACE(std::to_string(c.ranks) + " ranks " + c.environment);
    const fs::path out = scratch("ranks" + std::to_string(c.ranks) + ".h5");
    const auto o =
        mpi_run(c.ranks, "run " + s.plan.string() + " --output " + out.string(), c.environment);
    ASSERT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find(std::to_string(kPoints) + " computed, 0 reused"), std::string::npos)
        << o.text;
    if (c.ranks > 1) {
      EXPECT_NE(o.text.find(std::to_string(c.ranks) + " ranks (rank 0 serving and computing): "
                                                      "points computed per rank: "),
                std::string::npos)
          << o.text;
    }
    const auto same = compare(s.single, out);
    EXPECT_EQ(same.status, 0) << same.text;
  }
}

// The pids of mpirun's children: its ranks.
std::vector<pid_t> children(pid_t mpirun) {
  std::vector<pid_t> found;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string pid, comm, state;
    long parent = 0;
    if (stat >> pid >> comm >> state >> parent && parent == mpirun) {
      found.push_back(static_cast<pid_t>(std::stol(name)));
    }
  }
  return found;
}

// The pid of rank `rank` among mpirun's children (OMPI_COMM_WORLD_RANK in its environment).
std::optional<pid_t> rank_pid(pid_t mpirun, int rank) {
  const std::string wanted = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  for (const pid_t child : children(mpirun)) {
    std::ifstream environ("/proc/" + std::to_string(child) + "/environ", std::ios::binary);
    const std::string env{std::istreambuf_iterator<char>(environ), {}};
    std::size_t at = 0;
    for (std::size_t end; (end = env.find('\0', at)) != std::string::npos; at = end + 1) {
      if (env.compare(at, end - at, wanted) == 0) return child;
    }
  }
  return std::nullopt;
}

// An mpirun job started by start_mpirun, in a process group of its own. Every wait is bounded,
// and what still runs when the Job goes is killed, mpirun and its ranks (each rank is in a
// process group of its own, so they are found as mpirun's children; SIGKILL ends stopped ones
// too): a hang or a failed assertion fails the test by name and leaves nothing running.
class Job {
 public:
  explicit Job(pid_t pid) : pid_(pid) {}
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;
  ~Job() { kill_all(); }

  pid_t pid() const { return pid_; }
  // mpirun's wait status, once ended() or wait() said it ended.
  int status() const { return raw_; }

  // Whether mpirun has ended, without waiting.
  bool ended() {
    if (!ended_ && pid_ > 0 && waitpid(pid_, &raw_, WNOHANG) == pid_) ended_ = true;
    return ended_;
  }

  // Waits up to `seconds` for mpirun to end; past that kills the group and says false.
  bool wait(double seconds = kJobSeconds) {
    const auto start = Clock::now();
    while (!ended()) {
      if (std::chrono::duration<double>(Clock::now() - start).count() >= seconds) {
        kill_all();
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

 private:
  void kill_all() {
    if (pid_ <= 0 || ended_) return;
    for (const pid_t rank : children(pid_)) kill(rank, SIGKILL);
    kill(-pid_, SIGKILL);
    waitpid(pid_, &raw_, 0);
    ended_ = true;
  }

  pid_t pid_;
  int raw_ = 0;
  bool ended_ = false;
};

// mpirun -np 3 MPIRUN_OPTIONS of `impactid-mpi run PLAN --output OUT ARGUMENTS` in a child
// process of its own process group (output to a log).
std::unique_ptr<Job> start_mpirun(const fs::path& plan, const fs::path& out, const fs::path& log,
                                  const std::string& arguments,
                                  const std::string& mpirun_options = "") {
  const pid_t child = fork();
  if (child == 0) {
    setpgid(0, 0);
    // A process group of its own is a background one: mpirun must not read the terminal (it
    // would be stopped by SIGTTIN), so stdin is /dev/null.
    const int null = open("/dev/null", O_RDONLY);
    dup2(null, 0);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::string command = "exec " + kMpirun + " -np 3 -x OMP_NUM_THREADS=1 " + mpirun_options +
                          " " + IMPACTID_MPI_EXECUTABLE + " run " + plan.string() + " --output " +
                          out.string() + " " + arguments;
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Also here, so that the group exists before any kill(-pid) (the child may not have run yet).
  if (child > 0) setpgid(child, child);
  return std::make_unique<Job>(child);
}

std::unique_ptr<Job> start_mpirun(const fs::path& out, const fs::path& log, bool resume) {
  return start_mpirun(study().plan, out, log, resume ? "--resume" : "");
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Points done in the file so far; 0 while there is none (checkpoints replace it atomically, so a
// file that exists is complete).
long points_saved(const fs::path& file) {
  if (!fs::exists(file)) return 0;
  try {
    return read_results(file).points_done();
  } catch (const std::exception&) {
    return 0;
  }
}

// SIGKILL of one rank after the first checkpoint with a point in it ends the job (mpirun takes the
// others down); the file is a complete results file of part of the plan, and --resume on 3 ranks
// computes only the rest and ends with the single process's file.
void kill_rank_then_resume(int rank) {
  const Study& s = study();
  const fs::path out = scratch("killed" + std::to_string(rank) + ".h5");
  const fs::path log = scratch("killed" + std::to_string(rank) + ".log");
  const auto start = Clock::now();
  const auto job = start_mpirun(out, log, false);
  ASSERT_GT(job->pid(), 0);
  std::optional<pid_t> victim;
  bool ended = false;
  while (!ended && std::chrono::duration<double>(Clock::now() - start).count() < 120) {
    ended = job->ended();
    if (!ended && points_saved(out) > 0 && (victim = rank_pid(job->pid(), rank))) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_FALSE(ended) << "the job ended before a kill:\n" << read_text(log);
  ASSERT_TRUE(victim) << "rank " << rank << " not found";
  ASSERT_EQ(kill(*victim, SIGKILL), 0);
  ASSERT_TRUE(job->wait()) << "the job still ran " << kJobSeconds << " s after the kill:\n"
                           << read_text(log);
  const int raw = job->status();
  EXPECT_FALSE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0)
      << "the job went on without rank " << rank << ":\n"
      << read_text(log);

  StudyResults partial;
  ASSERT_NO_THROW(partial = read_results(out)) << "not a complete results file";
  const long saved = partial.points_done();
  EXPECT_GT(saved, 0);
  std::printf("mpi_run_test: rank %d killed; %ld of %ld points saved\n", rank, saved, kPoints);

  const auto resumed = start_mpirun(out, log, true);
  ASSERT_TRUE(resumed->wait()) << "the resumed job still ran after " << kJobSeconds << " s:\n"
                               << read_text(log);
  const std::string text = read_text(log);
  ASSERT_TRUE(WIFEXITED(resumed->status()) && WEXITSTATUS(resumed->status()) == 0) << text;
  EXPECT_NE(text.find(std::to_string(kPoints - saved) + " computed, " + std::to_string(saved) +
                      " reused"),
            std::string::npos)
      << text;
  const auto same = compare(s.single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

TEST(MpiRun, SigkillOfAWorkerThenResumeEndsWithTheSameFile) {
  kill_rank_then_resume(1);
}

TEST(MpiRun, SigkillOfRankZeroThenResumeEndsWithTheSameFile) {
  kill_rank_then_resume(0);
}

// A process's state letter in /proc (R, S, T for stopped, Z for a zombie…); empty if it is gone.
std::string process_state(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string skip, comm, state;
  return stat >> skip >> comm >> state ? state : std::string();
}

// A process that exists and is not a zombie.
bool alive(pid_t pid) {
  const std::string state = process_state(pid);
  return !state.empty() && state != "Z";
}

// What rank 0 says, with the results file written, when it ends the job without a rank.
const std::string kAbortLine = "impactid-mpi: rank(s) 2 stopped answering; the results are written";

// Runs `plan_text` under mpirun -np 3 with the stall options' defaults (10 times the expected
// time, at least 5 s: study/cli/mpi_stall.hpp) and stops rank 2 with SIGSTOP once the results file
// holds `saved` points (every worker has answered the plan by then, and holds work). The job must
// end within 60 s of the stop (plus 10 times the plan's single-process time, below), with status
// 0, saying that rank 2's work went to other ranks (`handed`) and that the job ended without it,
// and with the single process's file. Before the fix rank 0 waited for the stopped rank forever.
// Whatever is left of rank 2 is killed. With `self_stop` (mpirun's -x of a test hook), rank 2
// stops itself at the moment the hook names, and the test waits for that instead.
void stop_a_worker(const std::string& name, const std::string& plan_text, long saved,
                   const std::vector<std::string>& handed, const std::string& self_stop = "") {
  const fs::path plan = testing::write_file(scratch(name + ".toml"), plan_text);
  const fs::path single = scratch(name + "-single.h5");
  const auto single_start = Clock::now();
  const auto o =
      testing::run_impactid("run " + plan.string() + " --threads 2 --output " + single.string());
  ASSERT_EQ(o.status, 0) << o.text;
  // The stall bound is 10 times the slowest batch or search measured so far, and none takes
  // longer than the whole plan on one process: on a loaded machine the bound grows with it, so
  // the test's own bound does too (a fixed 60 s failed under a parallel ctest).
  const double single_seconds = std::chrono::duration<double>(Clock::now() - single_start).count();

  const fs::path out = scratch(name + "-stalled.h5");
  const fs::path log = scratch(name + "-stalled.log");
  fs::remove(out);
  const auto start = Clock::now();
  const auto job = start_mpirun(plan, out, log, "", self_stop);
  ASSERT_GT(job->pid(), 0);
  std::optional<pid_t> victim;
  bool ended = false;
  while (!ended && std::chrono::duration<double>(Clock::now() - start).count() < 120) {
    ended = job->ended();
    if (ended) break;
    if (self_stop.empty()) {
      if (points_saved(out) >= saved && (victim = rank_pid(job->pid(), 2))) break;
    } else if ((victim = rank_pid(job->pid(), 2)) && process_state(*victim) == "T") {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_FALSE(ended) << "the job ended before the stop:\n" << read_text(log);
  ASSERT_TRUE(victim) << "rank 2 not found";
  if (self_stop.empty()) {
    ASSERT_EQ(kill(*victim, SIGSTOP), 0);
  } else {
    ASSERT_EQ(process_state(*victim), "T") << "rank 2 did not stop itself:\n" << read_text(log);
  }
  const auto stopped = Clock::now();
  const double kBoundSeconds = 60 + 10 * single_seconds;
  // Rank 0 has written the file and called MPI_Abort (it says so): its part is done.
  bool aborting = false;
  // mpirun's own teardown after MPI_Abort, every rank gone, hung. Debian 12's mpirun (OpenMPI
  // 4.1.4 with an external PMIx) hung in PMIx_server_finalize, crashed there, or ended with a
  // non-zero status after an ORTE_ERROR_LOG on the abort's message, when the ranks it killed sat
  // in MPI_Finalize's collective; the workers now wait outside it (kTagFinalize, docs/scale.md),
  // but mpirun may still fail so (open-mpi/ompi#5528). That is not impactid's defect, and what the
  // test checks (rank 0 ends the job with the file written) is checked without it.
  bool teardown_hung = false;
  // Whether no rank is alive while mpirun still is, and since when.
  bool none_alive = false;
  Clock::time_point none_alive_since;
  while (!ended && std::chrono::duration<double>(Clock::now() - stopped).count() < kBoundSeconds) {
    ended = job->ended();
    if (ended) break;
    if (!aborting) aborting = read_text(log).find(kAbortLine) != std::string::npos;
    if (aborting) {
      const std::vector<pid_t> ranks = children(job->pid());
      if (std::any_of(ranks.begin(), ranks.end(), alive)) {
        none_alive = false;
      } else if (!none_alive) {
        none_alive = true;
        none_alive_since = Clock::now();
      } else if (std::chrono::duration<double>(Clock::now() - none_alive_since).count() > 10) {
        teardown_hung = true;
        break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - stopped).count();
  if (teardown_hung) {
    job->wait(0);  // kills mpirun
    ended = true;
  } else if (!ended) {  // the hang: let the rank go on, so that the job ends and leaves nothing
                        // behind
    kill(*victim, SIGCONT);
    job->wait(30);
  }
  if (alive(*victim)) {
    kill(*victim, SIGCONT);
    kill(*victim, SIGKILL);
  }
  const int raw = job->status();
  const std::string text = read_text(log);
  ASSERT_TRUE(ended) << "the job still ran " << kBoundSeconds << " s after rank 2 stopped:\n"
                     << text;
  std::printf("mpi_run_test: %s: rank 2 stopped; the job ended %.1f s later\n", name.c_str(),
              seconds);
  // The file is complete: mpirun's status is rank 0's, the run's own (unless mpirun's own
  // teardown hung or crashed, above).
  const bool teardown_failed =
      aborting && !(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) &&
      (teardown_hung || WIFSIGNALED(raw) || text.find("ORTE_ERROR_LOG") != std::string::npos);
  if (teardown_failed) {
    std::printf(
        "mpi_run_test: %s: mpirun's own teardown after MPI_Abort %s (OpenMPI's defect, "
        "docs/scale.md); the rest is checked\n",
        name.c_str(),
        teardown_hung      ? "hung, every rank gone"
        : WIFSIGNALED(raw) ? "crashed"
                           : "failed with an ORTE_ERROR_LOG");
  } else {
    ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << text;
  }
  for (const std::string& line : handed) EXPECT_NE(text.find(line), std::string::npos) << text;
  EXPECT_NE(text.find(kAbortLine), std::string::npos) << text;
  const auto same = compare(single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

// A sweep: kPlan on a 1000-element rod (about 2 s on one core), rank 2 stopped once an eighth of
// the points are saved, with most of the plan still to compute.
TEST(MpiRun, AStoppedWorkersBatchesGoToTheOtherRanksAndTheRunEnds) {
  std::string text = kPlan;
  text.replace(text.find("elements = 500"), 14, "elements = 1000");
  stop_a_worker("stall", text, kPoints / 8,
                {"impactid run: rank 2 has not answered batch ", ", out at rank 2 for ",
                 std::to_string(kPoints) + " computed, 0 reused"});
}

// OpenMPI's shared-memory transport made to need its sender for the whole of a rows message, as
// it does in a container without ptrace rights (no single-copy reads) and as TCP does between
// nodes: no single-copy mechanism, and an eager limit below any rows message.
const std::string kRowsNeedTheirSender =
    "--mca btl_vader_single_copy_mechanism none --mca btl_vader_eager_limit 1024";

// Rank 2 stops itself in the middle of sending its first rows (the test hook
// IMPACTID_MPI_STOP_IN_ROWS), the first part of the message delivered, the rest never. Before
// the fix (Inbox, study/cli/mpi_protocol.hpp) rank 0 matched that first part and waited in a
// blocking receive for the rest, so the watch for stalled ranks never ran: the CI run of
// 721771e hung so in the test above, the SIGSTOP falling while rank 2 sent.
TEST(MpiRun, AWorkerStoppedInTheMiddleOfSendingItsRowsDoesNotHoldRankZero) {
  stop_a_worker("stall-mid-send", kPlan, 0,
                {"impactid run: rank 2 has not answered batch ", ", out at rank 2 for ",
                 std::to_string(kPoints) + " computed, 0 reused"},
                "-x IMPACTID_MPI_STOP_IN_ROWS=2 " + kRowsNeedTheirSender);
}

// Cheap points (a 4-element rod, 50 625 of them, about 0.3 s on one core) grow the batches to
// hundreds of windows, messages past MPI's eager limit. Rank 0 sends them without blocking
// (mpi_protocol.hpp, Outbox): with 8b1d763's blocking MPI_Send, rank 0 and a worker each waited in
// MPI_Send to the other, and the job hung (3 tries of 3 here).
TEST(MpiRun, LargeBatchesOfCheapPointsDoNotDeadlock) {
  const fs::path plan = testing::write_file(scratch("cheap.toml"), R"(
[scene]
elements = 4
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 224 }
delta = { from = 0.0, to = 1.0, partitions = 224 }
)");
  const fs::path single = scratch("cheap-single.h5");
  const auto o =
      testing::run_impactid("run " + plan.string() + " --threads 2 --output " + single.string());
  ASSERT_EQ(o.status, 0) << o.text;
  const fs::path out = scratch("cheap.h5");
  const fs::path log = scratch("cheap.log");
  const auto job = start_mpirun(plan, out, log, "");
  ASSERT_GT(job->pid(), 0);
  const bool ended = job->wait(60);  // past 60 s the job (the deadlock) is killed
  const int raw = job->status();
  const std::string text = read_text(log);
  ASSERT_TRUE(ended) << "the job still ran after 60 s:\n" << text;
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << text;
  const auto same = compare(single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

// Shards (study/studies/shard.hpp) and MPI together: each shard on two ranks, then merged; the
// merged file is the single process's.
TEST(MpiRun, ShardsRunOverMpiMergeToTheSingleProcessFile) {
  const Study& s = study();
  std::string files;
  for (int k = 0; k < 2; ++k) {
    const fs::path out = scratch("shard" + std::to_string(k) + ".h5");
    const auto o = mpi_run(
        2,
        "run " + s.plan.string() + " --shard " + std::to_string(k) + "/2 --output " + out.string(),
        "-x OMP_NUM_THREADS=1");
    ASSERT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find("shard " + std::to_string(k) + "/2"), std::string::npos) << o.text;
    files += " " + out.string();
  }
  const fs::path merged = scratch("shards-merged.h5");
  const auto m = testing::run_impactid("merge" + files + " --output " + merged.string());
  ASSERT_EQ(m.status, 0) << m.text;
  const auto same = compare(s.single, merged);
  EXPECT_EQ(same.status, 0) << same.text;
}

// SIGUSR1 to mpirun, which passes it to every rank, stops the job as Ctrl-C stops a single
// process: rank 0 hands out no more work, collects what is running, saves it and exits with 130
// ("interrupted"); the workers ignore the signal. --resume then ends with the single run's file.
TEST(MpiRun, SigusrOneToMpirunStopsTheJobWithEverythingComputedSaved) {
  const Study& s = study();
  const fs::path out = scratch("usr1.h5");
  const fs::path log = scratch("usr1.log");
  const auto start = Clock::now();
  const auto job = start_mpirun(out, log, false);
  ASSERT_GT(job->pid(), 0);
  bool ended = false;
  long before = 0;
  while (!ended && std::chrono::duration<double>(Clock::now() - start).count() < 120) {
    ended = job->ended();
    if (!ended && (before = points_saved(out)) > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_FALSE(ended) << "the job ended before the signal:\n" << read_text(log);
  ASSERT_EQ(kill(job->pid(), SIGUSR1), 0);
  ASSERT_TRUE(job->wait()) << "the job still ran " << kJobSeconds << " s after SIGUSR1:\n"
                           << read_text(log);
  const int raw = job->status();
  const std::string text = read_text(log);
  // Rank 0's status is mpirun's, unless the run ended on its own before the signal reached it.
  ASSERT_TRUE(WIFEXITED(raw)) << text;
  const long saved = points_saved(out);
  if (WEXITSTATUS(raw) == 0) {
    GTEST_SKIP() << "the run ended before rank 0 saw the signal (" << saved << " points)";
  }
  EXPECT_EQ(WEXITSTATUS(raw), 130) << text;
  // The hint names the MPI program and the job's ranks, not the single-process impactid.
  EXPECT_NE(text.find("impactid run: interrupted; continue with: mpirun -np 3 impactid-mpi run "),
            std::string::npos)
      << text;
  // Everything computed is saved: at least the checkpoint's points, and what followed it.
  EXPECT_GE(saved, before);
  EXPECT_LT(saved, kPoints);

  const auto resumed = start_mpirun(out, log, true);
  ASSERT_TRUE(resumed->wait()) << "the resumed job still ran after " << kJobSeconds << " s:\n"
                               << read_text(log);
  ASSERT_TRUE(WIFEXITED(resumed->status()) && WEXITSTATUS(resumed->status()) == 0)
      << read_text(log);
  const auto same = compare(s.single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

// A worker that fails on point 200 stops the job: the message names the rank, the point with
// its parameters, and the cause; what was computed is saved; --resume finishes the file.
TEST(MpiRun, AnErrorOnAWorkerNamesThePointAndKeepsWhatWasComputed) {
  const Study& s = study();
  const fs::path out = scratch("error.h5");
  const auto o = mpi_run(3, "run " + s.plan.string() + " --output " + out.string(),
                         "-x OMP_NUM_THREADS=1 -x IMPACTID_MPI_FAIL_AT_POINT=200");
  EXPECT_EQ(o.status, 1) << o.text;
  // Point 200 is alpha index 9, delta index 11 of the 21 x 21 grid.
  EXPECT_NE(o.text.find(": point 200 (alpha = -0.275, delta = 0.55): failure injected by "
                        "IMPACTID_MPI_FAIL_AT_POINT=200"),
            std::string::npos)
      << o.text;
  EXPECT_NE(o.text.find("impactid run: rank "), std::string::npos) << o.text;
  const StudyResults partial = read_results(out);
  EXPECT_EQ(partial.status[200], kStatusNotDone);
  EXPECT_GT(partial.points_done(), 0);

  const auto resumed = mpi_run(2, "run " + s.plan.string() + " --resume --output " + out.string(),
                               "-x OMP_NUM_THREADS=1");
  ASSERT_EQ(resumed.status, 0) << resumed.text;
  EXPECT_NE(resumed.text.find(std::to_string(partial.points_done()) + " reused"), std::string::npos)
      << resumed.text;
  const auto same = compare(s.single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

// --- an optimisation's searches over the ranks -------------------------------------------------

// Six COBYLA searches of at most 40 evaluations each on an 80-element rod.
const char* kSearchPlan = R"(
[scene]
elements = 80
[method]
name = "hht"
[study]
kind = "optimize"
algorithm = "COBYLA"
objective = "eps_p"
max_evaluations = 40
starts = 6
[study.parameters]
delta = { from = 0.0, to = 1.0 }
alpha = { from = -0.5, to = 0.0 }
[study.constraints]
nop_p = { max = 15 }
)";

const Study& search_study() {
  static const Study s = [] {
    Study s;
    s.plan = testing::write_file(scratch("optimize.toml"), kSearchPlan);
    s.single = scratch("optimize-single.h5");
    const auto o = testing::run_impactid("run " + s.plan.string() + " --threads 2 --output " +
                                         s.single.string());
    EXPECT_EQ(o.status, 0) << o.text;
    return s;
  }();
  return s;
}

TEST(MpiRun, AnOptimisationsSearchesGiveTheSingleProcessFileOnTwoOrThreeRanks) {
  const Study& s = search_study();
  for (const auto& [ranks, environment] :
       {std::pair{2, "-x OMP_NUM_THREADS=1"}, std::pair{2, "-x OMP_NUM_THREADS=2"},
        std::pair{3, "-x OMP_NUM_THREADS=1"}}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks " + environment);
    const fs::path out = scratch("optimize-ranks" + std::to_string(ranks) + ".h5");
    const auto o =
        mpi_run(ranks, "run " + s.plan.string() + " --output " + out.string(), environment);
    ASSERT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find(std::to_string(ranks) +
                          " ranks (rank 0 serving and computing): searches run per rank: "),
              std::string::npos)
        << o.text;
    const auto same = compare(s.single, out);
    EXPECT_EQ(same.status, 0) << same.text;
  }
}

// A search that fails on a worker stops the job with its number and the cause; the searches
// that ended are saved, and --resume replays them and ends with the single run's file.
TEST(MpiRun, AnErrorInASearchNamesItAndKeepsTheSearchesThatEnded) {
  const Study& s = search_study();
  const fs::path out = scratch("optimize-error.h5");
  const auto o = mpi_run(3, "run " + s.plan.string() + " --output " + out.string(),
                         "-x OMP_NUM_THREADS=1 -x IMPACTID_MPI_FAIL_AT_SEARCH=4");
  EXPECT_EQ(o.status, 1) << o.text;
  EXPECT_NE(o.text.find(": search 4: failure injected by IMPACTID_MPI_FAIL_AT_SEARCH=4"),
            std::string::npos)
      << o.text;
  EXPECT_NE(o.text.find("every search that ended is saved"), std::string::npos) << o.text;
  const StudyResults partial = read_results(out);
  EXPECT_GT(partial.points_total(), 0);

  const auto resumed = mpi_run(2, "run " + s.plan.string() + " --resume --output " + out.string(),
                               "-x OMP_NUM_THREADS=1");
  ASSERT_EQ(resumed.status, 0) << resumed.text;
  EXPECT_NE(resumed.text.find(std::to_string(partial.points_total()) + " reused"),
            std::string::npos)
      << resumed.text;
  const auto same = compare(s.single, out);
  EXPECT_EQ(same.status, 0) << same.text;
}

// An optimisation long enough to stop a worker in: 12 searches on a 300-element rod (about 3 s
// on 3 ranks).
std::string stalled_search_plan() {
  std::string text = kSearchPlan;
  text.replace(text.find("elements = 80"), 13, "elements = 300");
  text.replace(text.find("starts = 6"), 10, "starts = 12");
  return text;
}

// That optimisation, rank 2 stopped once a search is saved; the search it holds goes to another
// rank.
TEST(MpiRun, AStoppedWorkersSearchesGoToTheOtherRanksAndTheRunEnds) {
  std::string text = stalled_search_plan();
  text += "[output]\ncheckpoint_seconds = 0.05\n";
  stop_a_worker("search-stall", text, 1,
                {"impactid run: rank 2 has not answered its searches for ", ", out at rank 2 for ",
                 "searches run per rank: "});
}

// A search's answer is two messages, its rows then its end. Rank 2 stops itself between the two
// (the test hook IMPACTID_MPI_STOP_AFTER_ROWS): rank 0 must not wait for the second, and hands
// rank 2's searches on as above. Before the fix it waited in a blocking probe for that end, so
// the watch for stalled ranks never ran and the job hung (1 run in 2 of the test above, when the
// SIGSTOP fell between the messages).
TEST(MpiRun, AWorkerStoppedBetweenASearchsRowsAndItsEndDoesNotHoldRankZero) {
  stop_a_worker(
      "search-halfway", stalled_search_plan(), 0,
      {"impactid run: rank 2 has not answered its searches for ", "searches run per rank: "},
      "-x IMPACTID_MPI_STOP_AFTER_ROWS=2");
}

// As AWorkerStoppedInTheMiddleOfSendingItsRowsDoesNotHoldRankZero, for a search's rows.
TEST(MpiRun, AWorkerStoppedInTheMiddleOfSendingASearchsRowsDoesNotHoldRankZero) {
  stop_a_worker(
      "search-mid-send", stalled_search_plan(), 0,
      {"impactid run: rank 2 has not answered its searches for ", "searches run per rank: "},
      "-x IMPACTID_MPI_STOP_IN_ROWS=2 " + kRowsNeedTheirSender);
}

}  // namespace
}  // namespace impactid
