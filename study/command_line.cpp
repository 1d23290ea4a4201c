#include "study/command_line.hpp"

#include <algorithm>
#include <iostream>

namespace impactid {

std::string option_name(const std::string& parameter) {
  std::string name = "--" + parameter;
  std::replace(name.begin(), name.end(), '_', '-');
  return name;
}

void add_parameter_options(CLI::App& command, GivenOptions& given,
                           std::initializer_list<ParameterGroup> groups) {
  for (const ParameterInfo& info : parameter_table()) {
    if (std::find(groups.begin(), groups.end(), info.group) == groups.end()) continue;
    std::string help = info.description;
    if (*info.unit) help = "[" + std::string(info.unit) + "] " + help;
    if (*info.methods) help += " {" + std::string(info.methods) + "}";
    const std::string name = info.name;
    auto* option = command.add_option_function<std::string>(
        option_name(name), [&given, name](const std::string& v) { given[name] = v; }, help);
    if (*info.choices) {
      option->type_name(info.choices);
    } else {
      option->type_name(info.kind == ParameterKind::integer ? "INT" : "NUMBER");
    }
  }
}

void report(const ParameterError& error, const std::string& command) {
  std::cerr << "impactid " << command << ": " << option_name(error.field) << " = " << error.value
            << ": " << error.constraint << '\n';
}

bool apply_options(const GivenOptions& given, SimulationSettings& settings,
                   const std::string& command) {
  for (const auto& [name, text] : given) {
    if (auto error = assign_text(settings, name, text)) {
      report(*error, command);
      return false;
    }
  }
  return true;
}

std::optional<Simulation> build_or_report(const SimulationSettings& settings,
                                          const std::string& command) {
  auto built = build(settings);
  if (auto* error = std::get_if<ParameterError>(&built)) {
    report(*error, command);
    return std::nullopt;
  }
  return std::get<Simulation>(std::move(built));
}

}  // namespace impactid
