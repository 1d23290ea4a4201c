#include "study/cli/plot_command.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/formats/hdf5_file.hpp"

#ifndef IMPACTID_FIGURES_SOURCE_DIR
#define IMPACTID_FIGURES_SOURCE_DIR ""
#endif

namespace impactid {
namespace {

namespace fs = std::filesystem;

struct PlotArguments {
  std::string file;
  std::string out;
  std::string format = "png";
};

fs::path own_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self;
}

int plot(const PlotArguments& args) {
  std::error_code ec;
  if (!fs::is_regular_file(args.file, ec)) {
    std::cerr << "impactid plot: " << args.file
              << (fs::exists(args.file, ec) ? ": is not a regular file\n" : ": no such file\n");
    return kExitBadInput;
  }
  // h5py, which reads the file for the figures, runs HDF5 inside Python: a damaged file that
  // crashes HDF5 would end the figures by a signal, unexplained. impactid's reader reads it
  // first, in a child process (study/formats/hdf5_file.hpp), and refuses it by name.
  try {
    const Hdf5Reader first_read(args.file, UncheckedFile::quiet);
  } catch (const Hdf5Error& e) {
    std::cerr << "impactid plot: " << e.what() << '\n';
    return kExitBadInput;
  }
  std::string tried;
  const std::optional<fs::path> figures = find_figures_dir(tried);
  if (!figures) {
    std::cerr << "impactid plot: the figure package (plot_results.py) is in none of: " << tried
              << "; set IMPACTID_FIGURES_DIR to the figures/ folder of impactid's source\n";
    return kExitFailure;
  }
  const char* python_env = std::getenv("IMPACTID_PYTHON");
  const std::string python = python_env && *python_env ? python_env : "/usr/bin/python3";
  if (access(python.c_str(), X_OK) != 0) {
    std::cerr << "impactid plot: " << python
              << ": no such program; plotting needs Debian's python3 with python3-matplotlib and "
                 "python3-h5py (scripts/install-deps installs them), or IMPACTID_PYTHON naming "
                 "another Python that has them\n";
    return kExitFailure;
  }
  std::vector<std::string> argv{python, (*figures / "plot_results.py").string(), args.file,
                                "--format", args.format};
  if (!args.out.empty()) {
    argv.push_back("--out");
    argv.push_back(args.out);
  }
  std::vector<char*> raw;
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  std::cout.flush();
  const pid_t child = fork();
  if (child < 0) {
    std::cerr << "impactid plot: cannot start " << python << '\n';
    return kExitFailure;
  }
  if (child == 0) {
    // The figures take the method list (their colours) from this program.
    if (const fs::path self = own_executable(); !self.empty())
      setenv("IMPACTID_EXECUTABLE", self.c_str(), 1);
    execv(python.c_str(), raw.data());
    std::cerr << "impactid plot: cannot run " << python << '\n';
    _exit(kExitFailure);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return kExitFailure;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  std::cerr << "impactid plot: " << python << " ended by signal " << WTERMSIG(status) << '\n';
  return kExitFailure;
}

}  // namespace

std::optional<fs::path> find_figures_dir(std::string& tried) {
  std::vector<fs::path> candidates;
  if (const char* dir = std::getenv("IMPACTID_FIGURES_DIR"); dir && *dir) {
    candidates.emplace_back(dir);  // when set, the only place: a test or a relocated package
  } else {
    if (const fs::path self = own_executable(); !self.empty()) {
      candidates.push_back(self.parent_path().parent_path() / "share" / "impactid" / "figures");
    }
    if (*IMPACTID_FIGURES_SOURCE_DIR) candidates.emplace_back(IMPACTID_FIGURES_SOURCE_DIR);
  }
  std::error_code ec;
  for (const fs::path& dir : candidates) {
    tried += (tried.empty() ? "" : ", ") + dir.string();
    if (fs::is_regular_file(dir / "plot_results.py", ec)) return dir;
  }
  return std::nullopt;
}

std::function<int()> add_plot_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "plot",
      "Draw a results file of any study kind (grid, list, optimize, work-precision, spectral) or "
      "a history file (simulate --history, a plan's [output] histories) as PNG or PDF figures, "
      "with Debian's /usr/bin/python3 and matplotlib");
  auto args = std::make_shared<PlotArguments>();
  command->add_option("file", args->file, "the HDF5 file to draw")->required();
  command->add_option("--out", args->out,
                      "folder for the figures (created; default: FILE without .h5, plus "
                      "-figures, beside it)");
  command->add_option("--format", args->format, "png or pdf (default png)")
      ->check(CLI::IsMember({"png", "pdf"}));
  return [command, args]() -> int {
    if (!command->parsed()) return -1;
    return plot(*args);
  };
}

}  // namespace impactid
