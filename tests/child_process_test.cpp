// run_in_child (study/formats/child_process.hpp): a function that returns or throws has ended;
// one that dies by a signal or exits non-zero has crashed; one that runs past the bound is
// timed out; and none of it touches this process.
#include "study/formats/child_process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <stdexcept>

namespace impactid {
namespace {

using Kind = ChildOutcome::Kind;

TEST(ChildProcess, ReturningOrThrowingIsEnding) {
  EXPECT_EQ(run_in_child([] {}, 5).kind, Kind::ended);
  EXPECT_EQ(run_in_child([] { throw std::runtime_error("an error is an ending"); }, 5).kind,
            Kind::ended);
}

TEST(ChildProcess, ASignalOrANonZeroExitIsACrashAndNamesIt) {
  const ChildOutcome segv = run_in_child([] { std::raise(SIGSEGV); }, 5);
  EXPECT_EQ(segv.kind, Kind::crashed);
  // Under AddressSanitizer its own handler reports the fault and aborts, or exits with 1.
  EXPECT_TRUE(segv.signal == SIGSEGV || segv.signal == SIGABRT || segv.exit_status != 0)
      << segv.signal << " " << segv.exit_status;
  // A sanitizer's report ends the child with exit status 1, not a signal.
  const ChildOutcome exited = run_in_child([] { _exit(3); }, 5);
  EXPECT_EQ(exited.kind, Kind::crashed);
  EXPECT_EQ(exited.signal, 0);
  EXPECT_EQ(exited.exit_status, 3);
}

TEST(ChildProcess, ALoopIsEndedAtTheBound) {
  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome looped = run_in_child(
      [] {
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
  run_in_child([&] { value = 2; }, 5);
  EXPECT_EQ(value, 1);
}

// The parent's signal mask is not the child's: with SIGALRM blocked here the bound still holds.
TEST(ChildProcess, TheBoundHoldsWhenTheCallerBlocksTheAlarm) {
  sigset_t alarm_only, before;
  sigemptyset(&alarm_only);
  sigaddset(&alarm_only, SIGALRM);
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &alarm_only, &before), 0);
  const ChildOutcome looped = run_in_child(
      [] {
        for (volatile bool forever = true; forever;) {
        }
      },
      1);
  pthread_sigmask(SIG_SETMASK, &before, nullptr);
  EXPECT_EQ(looped.kind, Kind::timed_out);
}

}  // namespace
}  // namespace impactid
