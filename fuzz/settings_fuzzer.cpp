// libFuzzer target: any bytes as an `impactid` command line, then as `impactid simulate`'s
// parameters, then (for tiny scenes) as one simulation.
//
// The input is split into lines, at most 64 arguments (argv[0] = "impactid"); an argument ends
// at its first NUL, as a real argv does. Three stages, each of which must not crash, trip a
// sanitizer or throw anything the command line does not expect:
//   1. the whole command line (every subcommand and option of study/cli/main.cpp) through CLI11:
//      only CLI::ParseError (including --help and --version) may come out. Nothing is run.
//   2. simulate's parameter options (add_parameter_options, study/cli/command_line.hpp) through
//      CLI11, then assign_text() for each given option and build() (study/plan/simulation_settings.hpp),
//      as apply_options() and build_or_report() do, minus their messages on stderr. An error
//      must name a parameter of the table: it is printed as that option (`--delta = 0.3: …`).
//   3. when the built scene is tiny ((elements + 1) × steps ≤ 1e5, a few milliseconds), one
//      simulation and its indicators (study/studies/evaluation.hpp), written to JSON in memory. Checked:
//      a run that is not ok has only NaN indicators (docs/conventions.md, "Status"); steps ≤
//      planned steps.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <typeinfo>
#include <variant>
#include <vector>

#include "study/cli/command_line.hpp"
#include "study/cli/merge_command.hpp"
#include "study/cli/run_command.hpp"
#include "study/cli/simulate_command.hpp"
#include "study/formats/json_writer.hpp"
#include "study/plan/simulation_settings.hpp"
#include "study/studies/evaluation.hpp"

namespace {

constexpr std::size_t kMaxArguments = 64;
constexpr double kMaxDofSteps = 1e5;

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "settings_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

// CLI11 wants argc/argv; `storage` owns the strings.
struct Argv {
  std::vector<std::string> storage;
  std::vector<const char*> pointers;
  explicit Argv(const std::string& input) {
    storage.emplace_back("impactid");
    // Each '\n' ends an argument; text after the last one is an argument too.
    std::size_t start = 0;
    while (start < input.size() && storage.size() <= kMaxArguments) {
      const std::size_t end = std::min(input.find('\n', start), input.size());
      storage.push_back(input.substr(start, end - start).c_str());  // up to the first NUL
      start = end + 1;
    }
    for (const std::string& s : storage) pointers.push_back(s.c_str());
  }
  int argc() const { return static_cast<int>(pointers.size()); }
  const char* const* argv() const { return pointers.data(); }
};

// Stage 1: the set-up of study/cli/main.cpp's main(), which is not a function of its own.
void parse_whole_command_line(const Argv& args) {
  CLI::App app{"impactid"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fuzz");
  // Kept alive through parse(), as main() keeps them: the options' callbacks write into state
  // that these functions own (compare's given options, for one).
  const std::function<int()> commands[] = {
      impactid::add_simulate_command(app), impactid::add_compare_command(app),
      impactid::add_run_command(app),      impactid::add_export_command(app),
      impactid::add_merge_command(app),
  };
  try {
    app.parse(args.argc(), args.argv());
  } catch (const CLI::ParseError&) {
  }
}

void check_not_ok_is_nan(const impactid::Evaluation& e) {
  const impactid::Indicators& i = e.indicators;
  const double values[] = {
      i.eps_p,       i.eps_v, i.nop_p, i.nop_v, i.p_max, i.p_max_ratio, i.contact_episodes,
      i.energy_ratio};
  for (const double v : values) {
    if (!std::isnan(v)) {
      finding(std::string("a run with status ") + impactid::to_string(e.summary.status) +
              " has an indicator that is not NaN");
    }
  }
}

void simulate_if_tiny(const impactid::Simulation& simulation) {
  const impactid::RodScene* rod = simulation.rod();  // settings from the command line: the rod
  if (!rod) return;
  const impactid::RodSceneDerived d = impactid::derive(*rod);
  const double dof_steps = (rod->elements + 1.0) * static_cast<double>(d.step_count);
  if (!(dof_steps <= kMaxDofSteps)) return;
  impactid::SimulationWorkspace workspace;
  const impactid::Evaluation e = impactid::evaluate(simulation, workspace);
  if (e.summary.steps > e.summary.planned_steps) finding("more steps than planned");
  if (e.summary.status != impactid::RunStatus::ok) check_not_ok_is_nan(e);
  std::ostringstream text;
  impactid::JsonWriter json(text);
  json.begin_object();
  json.key("status").value(impactid::to_string(e.summary.status));
  json.key("message").value(e.summary.message);
  for (const double v : {e.indicators.eps_p, e.indicators.eps_v, e.indicators.nop_p,
                         e.indicators.p_max, e.indicators.energy_ratio}) {
    json.key("x").value(v);
  }
  json.end_object();
}

// Stage 2 and 3.
void simulate_command_line(const Argv& args) {
  CLI::App app{"impactid"};
  auto* command = app.add_subcommand("simulate");
  impactid::GivenOptions given;
  impactid::add_parameter_options(
      *command, given,
      {impactid::ParameterGroup::method, impactid::ParameterGroup::scene,
       impactid::ParameterGroup::output});
  app.require_subcommand(1);
  try {
    app.parse(args.argc(), args.argv());
  } catch (const CLI::ParseError&) {
    return;  // not `simulate`, or not a valid one
  }
  impactid::SimulationSettings settings;
  for (const auto& [name, text] : given) {
    if (!impactid::find_parameter(name)) finding("an option for the unknown parameter " + name);
    if (const auto error = impactid::assign_text(settings, name, text)) {
      if (!impactid::find_parameter(error->field)) {
        finding("assign_text error names '" + error->field + "', not a parameter");
      }
      return;
    }
  }
  const auto built = impactid::build(settings);
  if (const auto* error = std::get_if<impactid::ParameterError>(&built)) {
    if (!impactid::find_parameter(error->field)) {
      finding("build() error names '" + error->field + "', not a parameter");
    }
    return;
  }
  simulate_if_tiny(std::get<impactid::Simulation>(built));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Argv args(std::string(reinterpret_cast<const char*>(data), size));
  try {
    parse_whole_command_line(args);
    simulate_command_line(args);
  } catch (const std::exception& e) {
    finding(std::string("threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}
