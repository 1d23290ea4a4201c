// impactid: identify the time-stepping method and its parameters for dynamic contact and
// impact problems. Entry point: parses the command line and runs one subcommand.
#include "study/cli/cli_main.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <functional>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "core/common/kernel_level.hpp"
#include "study/cli/command_line.hpp"
#include "study/cli/contact_laws_command.hpp"
#include "study/cli/merge_command.hpp"
#include "study/cli/methods_command.hpp"
#include "study/cli/model_export.hpp"
#include "study/cli/plot_command.hpp"
#include "study/cli/run_command.hpp"
#include "study/cli/simulate_command.hpp"
#include "study/cli/spectral_command.hpp"
#include "study/version.hpp"

namespace impactid {
namespace {

// Optimal string alignment distance: insertions, deletions, substitutions and transpositions of
// two adjacent characters, each one edit ("alpah" is one from "alpha").
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

// " did you mean simulate?": the candidates nearest to `word` if they are near enough to be a
// typo of it (1 edit in a word of up to 4 letters, 2 up to 8, 3 beyond), or that begin with it
// (a name cut short); "" when none is.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  const std::size_t limit = word.size() <= 4 ? 1 : word.size() <= 8 ? 2 : 3;
  std::size_t best = limit + 1;
  std::vector<std::string> nearest;
  for (const std::string& candidate : candidates) {
    const bool prefix = word.size() >= 3 && candidate.rfind(word, 0) == 0;
    const std::size_t d = prefix ? 1 : edit_distance(word, candidate);
    if (d < best) nearest.clear(), best = d;
    if (d == best && d <= limit) nearest.push_back(candidate);
  }
  if (nearest.empty()) return "";
  std::string text = " did you mean ";
  for (std::size_t k = 0; k < nearest.size(); ++k) {
    text += (k == 0 ? "" : k + 1 == nearest.size() ? " or " : ", ") + nearest[k];
  }
  return text + "?";
}

// After CLI11 refused the command line, the words it did not know with the nearest it knows: a
// command (`impactid simulat`), an option of the command (`--alpah`, `--alpah=0.1`). Empty when
// every command and option is known, and the error is another one (a missing value, a bad
// number), which CLI11's message then states.
std::vector<std::string> unknown_words(CLI::App& app, int argc, char** argv) {
  std::vector<std::string> messages;
  CLI::App* command = nullptr;
  std::string prefix = "impactid: ";
  for (int k = 1; k < argc; ++k) {
    const std::string word = argv[k];
    if (word == "--") break;
    CLI::App& scope = command ? *command : app;
    if (word.rfind("--", 0) == 0 && word.size() > 2) {
      const std::string name = word.substr(0, word.find('='));
      if (scope.get_option_no_throw(name)) continue;
      std::vector<std::string> names;
      for (const CLI::Option* option : scope.get_options()) {
        for (const std::string& long_name : option->get_lnames()) names.push_back("--" + long_name);
      }
      messages.push_back(prefix + name + " is not an option" +
                         (command ? " of impactid " + command->get_name() : std::string()) + ";" +
                         did_you_mean(name, names));
    } else if (!command && word.rfind('-', 0) != 0) {
      const auto found = app.get_subcommands([&](CLI::App* s) { return s->get_name() == word; });
      if (!found.empty()) {
        command = found.front();
        prefix = "impactid " + word + ": ";
        continue;
      }
      std::vector<std::string> names;
      for (const CLI::App* s : app.get_subcommands([](CLI::App*) { return true; })) {
        names.push_back(s->get_name());
      }
      messages.push_back(prefix + word + " is not a command;" + did_you_mean(word, names));
      break;  // what follows belongs to the command meant
    }
  }
  for (std::string& m : messages) {
    if (m.back() == ';') m.back() = '.';
  }
  return messages;
}

}  // namespace

int impactid_main(int argc, char** argv, const Runners& runners) {
  CLI::App app{
      "impactid: time-stepping methods for dynamic contact and impact problems "
      "(after Serfozo & Pere 2022, doi:10.1556/606.2022.00599)",
      "impactid"};  // the usage line's name, whatever the path the program was started by
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(impactid::kVersion) + " (" +
                                        impactid::kGitRevision + ")\nkernels " +
                                        describe_kernel_selection());
  // A file size limit (ulimit -f, a batch system's) reached by a write raises SIGXFSZ, whose
  // default action kills the program with everything unsaved; ignored, the write fails with
  // EFBIG and the writer reports it as any other write error, the previous file intact.
  std::signal(SIGXFSZ, SIG_IGN);
  // A level the processor lacks would fault at its first instruction: refused before anything
  // runs (IMPACTID_KERNELS, core/common/kernel_level.hpp).
  if (const KernelSelection& kernels = kernel_selection(); !kernels.error.empty()) {
    std::cerr << "impactid: " << kernels.error << '\n';
    return impactid::kExitBadInput;
  }
  std::vector<std::function<int()>> commands{
      impactid::add_simulate_command(app), impactid::add_compare_command(app),
      impactid::add_spectral_command(app), impactid::add_run_command(app, runners),
      impactid::add_export_command(app),   impactid::add_export_model_command(app),
      impactid::add_methods_command(app),  impactid::add_contact_laws_command(app),
      impactid::add_merge_command(app),    impactid::add_plot_command(app),
  };
  if (argc <= 1) {  // nothing asked: what there is to ask, as --help gives it
    std::cout << app.help();
    return 0;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::vector<std::string> unknown = unknown_words(app, argc, argv);
    if (unknown.empty()) {
      app.exit(e);  // prints CLI11's message
    } else {
      for (const std::string& line : unknown) std::cerr << line << '\n';
      std::cerr << "Run with --help for more information.\n";
    }
    return impactid::kExitBadInput;
  }
  // The commands report their own errors; this is the last line of defence (out of memory, a
  // defect), so that nothing ends in an abort without a word.
  try {
    for (const auto& run : commands) {
      if (const int status = run(); status >= 0) return status;
    }
  } catch (const std::exception& e) {
    std::cerr << "impactid: " << e.what() << '\n';
    return impactid::kExitFailure;
  }
  return impactid::kExitBadInput;
}

}  // namespace impactid
