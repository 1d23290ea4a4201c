#include "study/formats/child_process.hpp"

#include <fcntl.h>
#include <malloc.h>
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
    // Memory malloc hands out is filled with a pattern here (glibc's M_PERTURB; a no-op under the
    // sanitizers, whose malloc fills it already), so that a use of it before it is set fails in
    // the child rather than in whichever process the heap's leftovers happen to make fail: HDF5
    // 1.10 frees pointers of a link table it never set when a damaged group's links fail to
    // decode (H5G__link_release_table, under valgrind: "conditional jump depends on uninitialised
    // values" in H5MM_xfree), which crashed a parent whose child had read the same file without
    // harm (fuzz/corpus/results/regression-hdf5-link-table-never-set). glibc's per-thread cache
    // (blocks up to 1032 bytes) hands blocks back unfilled: for those the child is no surer than
    // the parent.
    mallopt(M_PERTURB, 0xA5);
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
