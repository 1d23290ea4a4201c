#include "study/formats/child_process.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <exception>

// The sanitizers' runtime, when linked in: its death callback is the parent's (libFuzzer saves
// the input as a finding from it), not the child's, whose crash is an answer.
extern "C" void __sanitizer_set_death_callback(void (*callback)()) __attribute__((weak));

namespace impactid {

ChildOutcome run_in_child(const std::function<void()>& work, double seconds) {
  const pid_t child = fork();
  if (child < 0) return {};
  if (child == 0) {
    // The parent's handlers and mask are not the child's business: a crash must end it, and
    // the alarm must reach it even if the calling thread blocked signals.
    for (const int s : {SIGALRM, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(s, SIG_DFL);
    sigset_t all;
    sigemptyset(&all);
    sigprocmask(SIG_SETMASK, &all, nullptr);
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDERR_FILENO);
    alarm(static_cast<unsigned>(std::ceil(std::max(1.0, seconds))));
    // Nothing here takes or gives back memory, nor changes how malloc does (not even mallopt,
    // which consolidates the heap): the work meets the heap as this process left it, as the
    // parent's own read after it does (study/formats/first_read.cpp says why).
    try {
      work();
    } catch (...) {  // an error is an ending; the parent meets it again, with its message
    }
    _exit(0);
  }
  int raw = 0;
  while (waitpid(child, &raw, 0) < 0) {
    if (errno != EINTR) return {};  // SIGCHLD ignored by the program: the status is lost
  }
  ChildOutcome outcome;
  if (WIFEXITED(raw)) {
    outcome.kind = WEXITSTATUS(raw) == 0 ? ChildOutcome::Kind::ended : ChildOutcome::Kind::crashed;
    outcome.exit_status = WEXITSTATUS(raw);
  } else if (WIFSIGNALED(raw)) {
    outcome.signal = WTERMSIG(raw);
    outcome.kind =
        outcome.signal == SIGALRM ? ChildOutcome::Kind::timed_out : ChildOutcome::Kind::crashed;
  }
  return outcome;
}

}  // namespace impactid
