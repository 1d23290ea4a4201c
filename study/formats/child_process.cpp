#include "study/formats/child_process.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <exception>
#include <mutex>
#include <string_view>

// The sanitizers' runtime, when linked in: its death callback is the parent's (libFuzzer saves
// the input as a finding from it), not the child's, whose crash is an answer.
extern "C" void __sanitizer_set_death_callback(void (*callback)()) __attribute__((weak));

namespace impactid {

namespace {

// Held from a pipe's creation to the parent's close of its write end: a child forked by another
// thread in between would hold that end too, and the parent's read would wait for that child.
std::mutex& fork_mutex() {
  static std::mutex forks;
  return forks;
}

}  // namespace

bool write_output(int output, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(output, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

ChildOutcome run_in_child(const std::function<void(int output)>& work, double seconds) {
  std::unique_lock forks(fork_mutex());
  int channel[2];
  if (pipe2(channel, O_CLOEXEC) != 0) return {};
  const pid_t child = fork();
  if (child < 0) {
    close(channel[0]);
    close(channel[1]);
    return {};
  }
  if (child == 0) {
    close(channel[0]);
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
    try {
      work(channel[1]);
    } catch (...) {  // an error is an ending; the parent meets it again, with its message
    }
    _exit(0);
  }
  close(channel[1]);
  forks.unlock();
  ChildOutcome outcome;
  // Until the child ends (it returned, crashed or met its alarm), which closes the pipe.
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(channel[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    outcome.output.append(buffer, static_cast<std::size_t>(n));
  }
  close(channel[0]);
  int raw = 0;
  while (waitpid(child, &raw, 0) < 0) {
    if (errno != EINTR) return {};  // SIGCHLD ignored by the program: the status is lost
  }
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
