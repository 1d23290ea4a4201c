#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/cli/run_command.hpp"
#include "study/io/results_file.hpp"

namespace impactid {

std::function<int()> add_export_command(CLI::App& app) {
  auto* command = app.add_subcommand(
      "export",
      "Write the surfaces of a results file as CSV: numbers in their shortest exact form, columns "
      "that are NaN at every point left out (and named on stderr)");
  struct Arguments {
    std::string file, csv;
  };
  auto args = std::make_shared<Arguments>();
  command->add_option("file", args->file, "Results file written by impactid run")
      ->required()
      ->type_name("FILE.h5");
  command->add_option("--csv", args->csv, "Folder for the CSV files (created if missing)")
      ->required()
      ->type_name("DIR");
  return [command, args]() -> int {
    if (!command->parsed()) return -1;
    try {
      const StudyResults results = read_results(args->file);
      const std::vector<std::string> skipped = export_csv(results, args->csv);
      std::cerr << "impactid export: " << results.points_done() << " of " << results.points_total()
                << " points done; wrote " << args->csv << "/points.csv"
                << (results.dimensions.size() == 2 ? " and one matrix per indicator" : "") << '\n';
      if (!skipped.empty()) {
        std::string names;
        for (const std::string& name : skipped) names += (names.empty() ? "" : ", ") + name;
        std::cerr << "impactid export: left out, NaN at every point: " << names << '\n';
      }
    } catch (const std::exception& e) {
      std::cerr << "impactid export: " << e.what() << '\n';
      return kExitFailure;
    }
    return 0;
  };
}

}  // namespace impactid
