// Running the impactid binary from a test, as a user would from a shell.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

namespace impactid::testing {

struct CommandOutput {
  int status;        ///< exit status, −1 if the process did not exit normally
  std::string text;  ///< stdout and stderr together
};

/// Runs `impactid <arguments>` (IMPACTID_EXECUTABLE, set by tests/CMakeLists.txt).
inline CommandOutput run_impactid(const std::string& arguments) {
  const std::string command = std::string(IMPACTID_EXECUTABLE) + " " + arguments + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string text;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe.get())) text += buffer.data();
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

}  // namespace impactid::testing
