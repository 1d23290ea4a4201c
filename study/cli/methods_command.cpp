#include "study/cli/methods_command.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/contact/contact_law_registry.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/rod_scene.hpp"
#include "study/formats/json_writer.hpp"

namespace impactid {
namespace {

// A parameter's default as text: the value the method's defaults report (for Newmark's beta and
// gamma, those eq. 13 gives at the default delta), or its choice word.
std::string default_text(const MethodDescriptor& method, const MethodParameter& parameter) {
  const MethodParams defaults = default_params(method.kind);
  if (parameter.choice) {
    for (const auto& [name, word] : method.choices(defaults)) {
      if (std::string_view(name) == parameter.name) return word;
    }
    return "";
  }
  const auto value = reported_value(defaults, parameter.name);
  if (!value) return "none";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", *value);
  return text;
}

// The contact laws a method takes (contact_law_refusal: every law it does not refuse).
std::vector<const char*> laws_taken(const MethodDescriptor& method) {
  std::vector<const char*> out;
  for (const ContactLawDescriptor& law : contact_law_registry()) {
    if (!contact_law_refusal(method, law.law)) out.push_back(law.name);
  }
  return out;
}

void write_text() {
  // Equation numbers without a paper are those of the benchmark impactid grew from; every other
  // reference is named with its paper and DOI.
  std::printf(
      "Each method with its paper; \"eq. N\" is an equation of Serfozo & Pere 2022, "
      "doi:10.1556/606.2022.00599.\n\n");
  for (const MethodDescriptor& m : method_registry()) {
    std::printf("%s\n  %s\n", m.name, m.summary);
    for (const char* name : m.parameters) {
      const MethodParameter& p = *find_method_parameter(name);
      std::string option = p.name;
      std::replace(option.begin(), option.end(), '_', '-');
      std::printf("  --%-14s default %-10s %s\n", option.c_str(), default_text(m, p).c_str(),
                  p.description);
    }
    std::string derived;
    for (const ReportedValue& v : m.values(default_params(m.kind))) {
      if (v.derived) derived += std::string(derived.empty() ? "" : ", ") + v.name;
    }
    if (!derived.empty()) std::printf("  derived: %s\n", derived.c_str());
    if (m.massless_dofs) {
      std::printf("  massless contact DOFs (mass = redistributed|singular): %s\n", m.massless_dofs);
    } else {
      std::printf("  mass: lumped|consistent only (refuses redistributed|singular)\n");
    }
    std::string laws;
    for (const char* law : laws_taken(m)) laws += std::string(laws.empty() ? "" : "|") + law;
    std::printf("  contact laws: %s\n", laws.c_str());
  }
  std::printf(
      "\nOn the command line --delta; in a plan delta = 0.3 under [method] or as a sweep "
      "axis.\n\nMass treatments (--mass, plan key mass, a sweep axis too):\n");
  for (const MassMatrix mass : kMassMatrices) {
    std::printf("  %-14s %s\n", to_string(mass), mass_matrix_description(mass));
  }
}

// The mass treatments a method takes: every one if it steps massless DOFs, else those without.
std::vector<const char*> masses_taken(const MethodDescriptor& method) {
  std::vector<const char*> out;
  for (const MassMatrix mass : kMassMatrices) {
    if (method.massless_dofs || !has_massless_dofs(mass)) out.push_back(to_string(mass));
  }
  return out;
}

}  // namespace

std::string method_label(const MethodDescriptor& method) {
  const std::string_view summary = method.summary;
  std::size_t end = summary.size();
  for (const std::string_view stop : {" (", " with "}) {
    end = std::min(end, summary.find(stop));
  }
  return std::string(summary.substr(0, end));
}

void write_methods_json(std::ostream& out) {
  JsonWriter json(out);
  json.begin_array();
  for (const MethodDescriptor& m : method_registry()) {
    json.begin_object();
    json.key("name").value(m.name);
    json.key("label").value(method_label(m));
    json.key("summary").value(m.summary);
    json.key("parameters").begin_array();
    for (const char* name : m.parameters) {
      const MethodParameter& p = *find_method_parameter(name);
      json.begin_object();
      json.key("name").value(p.name);
      json.key("kind").value(p.choice ? "choice" : "real");
      if (p.choice) json.key("choices").value(p.choices);
      const MethodParams defaults = default_params(m.kind);
      if (p.choice) {
        json.key("default").value(default_text(m, p));
      } else if (const auto v = reported_value(defaults, p.name)) {  // full precision
        json.key("default").value(*v);
      } else {
        json.key("default").null();
      }
      json.key("description").value(p.description);
      json.end_object();
    }
    json.end_array();
    json.key("derived").begin_array();
    for (const ReportedValue& v : m.values(default_params(m.kind))) {
      if (v.derived) json.value(v.name);
    }
    json.end_array();
    // The mass treatments (plan key `mass`) it takes, and how it steps a massless contact DOF.
    json.key("masses").begin_array();
    for (const char* mass : masses_taken(m)) json.value(mass);
    json.end_array();
    if (m.massless_dofs) {
      json.key("massless_dofs").value(m.massless_dofs);
    } else {
      json.key("massless_dofs").null();
    }
    // The contact laws (plan key `contact`) it takes.
    json.key("contact_laws").begin_array();
    for (const char* law : laws_taken(m)) json.value(law);
    json.end_array();
    json.end_object();
  }
  json.end_array();
  out << '\n';
}

std::function<int()> add_methods_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "methods", "List the time-stepping methods, their parameters and defaults");
  auto json = std::make_shared<bool>(false);
  command->add_flag("--json", *json, "print the list as JSON");
  return [command, json]() -> int {
    if (!command->parsed()) return -1;
    if (*json) {
      write_methods_json(std::cout);
    } else {
      write_text();
    }
    return 0;
  };
}

}  // namespace impactid
