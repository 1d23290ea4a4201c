#include "study/cli/command_line.hpp"

#include <algorithm>
#include <iostream>

#include "study/plan/plan.hpp"

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
  // A scene of bodies' keys are dotted paths (--set or the scene file), not options.
  const bool scene_key = error.field.find('.') != std::string::npos || error.field == "body" ||
                         error.field == "primary_contact";
  std::cerr << "impactid " << command << ": "
            << (scene_key ? error.field : option_name(error.field)) << " = " << error.value << ": "
            << error.constraint << '\n';
}

void add_scene_options(CLI::App& command, SceneOptions& options) {
  command
      .add_option("--scene", options.file,
                  "A scene of bodies (or the one-body rod) from a TOML scene file; the other "
                  "scene options apply on top of it")
      ->type_name("FILE.toml");
  command
      .add_option("--set", options.set,
                  "Set a key of the scene of bodies by its dotted path, e.g. "
                  "body.striker.velocity=2000 or body.bar.segment.1.area=4 (repeatable)")
      ->type_name("KEY=VALUE");
}

bool apply_scene_options(const SceneOptions& options, SimulationSettings& settings,
                         const std::string& command) {
  if (!options.file.empty()) {
    try {
      settings = load_scene_file(options.file);
    } catch (const PlanError& error) {
      std::cerr << "impactid " << command << ": " << error.what() << '\n';
      return false;
    }
  }
  for (const std::string& item : options.set) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << "impactid " << command << ": --set = " << item << ": must be KEY=VALUE\n";
      return false;
    }
    if (auto error = assign_text(settings, item.substr(0, eq), item.substr(eq + 1))) {
      // Named as the user gave it (--set KEY=VALUE), not as the option --KEY it may also be.
      std::cerr << "impactid " << command << ": --set " << error->field << " = " << error->value
                << ": " << error->constraint << '\n';
      return false;
    }
  }
  return true;
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
