// impactid: identify the time-stepping method and its parameters for dynamic contact and
// impact problems. Entry point: parses the command line and runs one subcommand.
#include "study/cli/cli_main.hpp"

#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/cli/merge_command.hpp"
#include "study/cli/methods_command.hpp"
#include "study/cli/model_export.hpp"
#include "study/cli/plot_command.hpp"
#include "study/cli/run_command.hpp"
#include "study/cli/simulate_command.hpp"
#include "study/cli/spectral_command.hpp"
#include "study/version.hpp"

namespace impactid {

int impactid_main(int argc, char** argv, const Runners& runners) {
  CLI::App app{
      "impactid: time-stepping methods for dynamic contact and impact problems "
      "(after Serfozo & Pere 2022, doi:10.1556/606.2022.00599)"};
  app.require_subcommand(1);
  app.set_version_flag("--version",
                       std::string(impactid::kVersion) + " (" + impactid::kGitRevision + ")");
  std::vector<std::function<int()>> commands{
      impactid::add_simulate_command(app), impactid::add_compare_command(app),
      impactid::add_spectral_command(app), impactid::add_run_command(app, runners),
      impactid::add_export_command(app),   impactid::add_export_model_command(app),
      impactid::add_methods_command(app),  impactid::add_merge_command(app),
      impactid::add_plot_command(app),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints CLI11's message
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
