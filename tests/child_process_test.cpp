// run_in_child (study/formats/child_process.hpp): a function that returns or throws has ended;
// one that dies by a signal or exits non-zero has crashed; one that runs past the bound is
// timed out; none of it touches this process, and what it writes to its output arrives whole.
#include "study/formats/child_process.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <stdexcept>
#include <string>

namespace impactid {
namespace {

using Kind = ChildOutcome::Kind;

TEST(ChildProcess, ReturningOrThrowingIsEnding) {
  EXPECT_EQ(run_in_child([](int) {}, 5).kind, Kind::ended);
  EXPECT_EQ(run_in_child([](int) { throw std::runtime_error("an error is an ending"); }, 5).kind,
            Kind::ended);
}

TEST(ChildProcess, ASignalOrANonZeroExitIsACrashAndNamesIt) {
  const ChildOutcome segv = run_in_child([](int) { std::raise(SIGSEGV); }, 5);
  EXPECT_EQ(segv.kind, Kind::crashed);
  // Under AddressSanitizer its own handler reports the fault and aborts, or exits with 1.
  EXPECT_TRUE(segv.signal == SIGSEGV || segv.signal == SIGABRT || segv.exit_status != 0)
      << segv.signal << " " << segv.exit_status;
  // A sanitizer's report ends the child with exit status 1, not a signal.
  const ChildOutcome exited = run_in_child([](int) { _exit(3); }, 5);
  EXPECT_EQ(exited.kind, Kind::crashed);
  EXPECT_EQ(exited.signal, 0);
  EXPECT_EQ(exited.exit_status, 3);
}

TEST(ChildProcess, ALoopIsEndedAtTheBound) {
  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome looped = run_in_child(
      [](int) {
        for (volatile bool forever = true; forever;) {
        }
      },
      1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(looped.kind, Kind::timed_out);
  EXPECT_GE(seconds, 0.9);
  EXPECT_LT(seconds, 30);
}

TEST(ChildProcess, TheChildsWritesStayInTheChild) {
  int value = 1;
  run_in_child([&](int) { value = 2; }, 5);
  EXPECT_EQ(value, 1);
}

// What the child writes to its output reaches this process whole, past a pipe's buffer, and
// under a limit on file sizes (a pipe is not a file: ulimit -f does not stop it).
TEST(ChildProcess, TheChildsOutputReachesTheParentWhole) {
  std::string bytes(5 << 20, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 7919 % 251);
  rlimit before{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &before), 0);
  rlimit small = before;
  small.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const ChildOutcome written =
      run_in_child([&](int output) { if (!write_output(output, bytes)) _exit(9); }, 30);
  setrlimit(RLIMIT_FSIZE, &before);
  EXPECT_EQ(written.kind, Kind::ended) << written.exit_status;
  EXPECT_TRUE(written.output == bytes) << written.output.size() << " bytes of " << bytes.size();
  // A child that crashed after writing: its bytes are what it wrote, its outcome a crash.
  const ChildOutcome crashed = run_in_child(
      [](int output) {
        write_output(output, "half");
        std::raise(SIGSEGV);
      },
      5);
  EXPECT_EQ(crashed.kind, Kind::crashed);
  EXPECT_EQ(crashed.output, "half");
}

// The parent's signal mask is not the child's: with SIGALRM blocked here the bound still holds.
TEST(ChildProcess, TheBoundHoldsWhenTheCallerBlocksTheAlarm) {
  sigset_t alarm_only, before;
  sigemptyset(&alarm_only);
  sigaddset(&alarm_only, SIGALRM);
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &alarm_only, &before), 0);
  const ChildOutcome looped = run_in_child(
      [](int) {
        for (volatile bool forever = true; forever;) {
        }
      },
      1);
  pthread_sigmask(SIG_SETMASK, &before, nullptr);
  EXPECT_EQ(looped.kind, Kind::timed_out);
}

}  // namespace
}  // namespace impactid
