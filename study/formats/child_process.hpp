// Runs a function in a child process (fork) to learn whether it ends: a probe for work that may
// crash or loop in a library we cannot fix, such as HDF5 reading a damaged file
// (study/formats/hdf5_file.hpp). The child's crash or hang is the child's: this process goes on
// and reports it.
//
// The child is a copy of this process with only the calling thread, so the function must not
// need the others (nor locks they may hold: HDF5 is called from one thread at a time here). It
// runs with its stderr sent to /dev/null (the parent reports, once), SIGALRM at `seconds`, and
// the default action for the crash signals; it ends with _exit, so no atexit handler and no
// stdio buffer of the parent's runs twice. An exception the function throws counts as ending;
// what the work computes reaches the parent only through what it writes (a file descriptor
// opened before the call: study/formats/first_read.cpp).
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace impactid {

/// How the function run by run_in_child ended.
struct ChildOutcome {
  enum class Kind {
    ended,      ///< returned or threw
    crashed,    ///< died by a signal, or exited non-zero (a sanitizer's report)
    timed_out,  ///< still running after the bound: killed by SIGALRM
    not_run,    ///< fork failed (no memory, no process slot): the caller decides
  };
  Kind kind = Kind::not_run;
  int signal = 0;       ///< crashed by a signal: which
  int exit_status = 0;  ///< crashed by exiting: the status
  std::string output;   ///< what the child wrote to its output before it ended
};

/// Runs `work` in a child process for at most `seconds` (≥ 1, rounded up) and says how it ended.
/// `work` is given its output, the write end of a pipe (write_output), whose bytes this process
/// reads while the child runs: a pipe, not a file, so that a limit on file sizes (ulimit -f)
/// or a full disk does not stop them.
ChildOutcome run_in_child(const std::function<void(int output)>& work, double seconds);

/// Writes all of `bytes` to a child's output; false when the pipe failed.
bool write_output(int output, std::string_view bytes);

}  // namespace impactid
