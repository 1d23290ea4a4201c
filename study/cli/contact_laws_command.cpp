#include "study/cli/contact_laws_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "core/contact/contact_law_registry.hpp"
#include "study/formats/json_writer.hpp"

namespace impactid {
namespace {

// A parameter's default as text: its value in a default ContactTreatment, "none" when unset
// (penalty_stiffness: the factor applies).
std::string default_text(const ContactLawParameter& parameter) {
  const double value = parameter.value(ContactTreatment{});
  if (std::isnan(value)) return "none";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

void write_text() {
  for (const ContactLawDescriptor& law : contact_law_registry()) {
    std::printf("%s\n  %s\n", law.name, law.summary);
    for (const char* name : law.parameters) {
      const ContactLawParameter& p = *find_contact_law_parameter(name);
      std::string option = p.name;
      std::replace(option.begin(), option.end(), '_', '-');
      std::printf("  --%-26s default %-6s %s%s%s%s\n", option.c_str(), default_text(p).c_str(),
                  *p.unit ? "[" : "", p.unit, *p.unit ? "] " : "", p.description);
    }
  }
  std::printf(
      "\nOn the command line --contact penalty --penalty-factor 10; in a plan contact = "
      "\"penalty\" under [scene], or as a sweep axis.\n");
}

void write_json() {
  JsonWriter json(std::cout);
  json.begin_array();
  for (const ContactLawDescriptor& law : contact_law_registry()) {
    json.begin_object();
    json.key("name").value(law.name);
    json.key("summary").value(law.summary);
    json.key("parameters").begin_array();
    for (const char* name : law.parameters) {
      const ContactLawParameter& p = *find_contact_law_parameter(name);
      json.begin_object();
      json.key("name").value(p.name);
      json.key("kind").value(p.integer ? "integer" : "real");
      json.key("unit").value(p.unit);
      const double value = p.value(ContactTreatment{});
      if (std::isnan(value)) {
        json.key("default").null();
      } else {
        json.key("default").value(value);  // full precision
      }
      json.key("description").value(p.description);
      json.end_object();
    }
    json.end_array();
    json.end_object();
  }
  json.end_array();
  std::cout << '\n';
}

}  // namespace

std::function<int()> add_contact_laws_command(CLI::App& app) {
  CLI::App* command =
      app.add_subcommand("contact-laws", "List the contact laws, their parameters and defaults");
  auto json = std::make_shared<bool>(false);
  command->add_flag("--json", *json, "print the list as JSON");
  return [command, json]() -> int {
    if (!command->parsed()) return -1;
    if (*json) {
      write_json();
    } else {
      write_text();
    }
    return 0;
  };
}

}  // namespace impactid
