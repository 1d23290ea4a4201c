#include "core/contact/contact_law_registry.hpp"

#include <array>
#include <vector>

namespace impactid {

std::span<const ContactLawDescriptor> contact_law_registry() {
  // Built on first use, after each law's file has made its descriptor.
  static const std::array<ContactLawDescriptor, 4> laws{
      lagrange_law(), penalty_law(), augmented_lagrangian_law(), paoli_schatzman_law()};
  return laws;
}

const ContactLawDescriptor& descriptor(ContactLaw law) {
  for (const ContactLawDescriptor& d : contact_law_registry()) {
    if (d.law == law) return d;
  }
  return contact_law_registry().front();  // unreachable: every ContactLaw is registered
}

const ContactLawDescriptor* find_contact_law(std::string_view name) {
  for (const ContactLawDescriptor& d : contact_law_registry()) {
    if (name == d.name) return &d;
  }
  return nullptr;
}

std::string contact_law_names() {
  std::string out;
  for (const ContactLawDescriptor& d : contact_law_registry()) {
    out += (out.empty() ? "" : "|") + std::string(d.name);
  }
  return out;
}

std::span<const ContactLawParameter> contact_law_parameters() {
  static const std::vector<ContactLawParameter> parameters = [] {
    std::vector<ContactLawParameter> out;
    for (const ContactLawDescriptor& d : contact_law_registry()) {
      out.insert(out.end(), d.introduces.begin(), d.introduces.end());
    }
    return out;
  }();
  return parameters;
}

const ContactLawParameter* find_contact_law_parameter(std::string_view name) {
  for (const ContactLawParameter& p : contact_law_parameters()) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

bool law_takes(const ContactLawDescriptor& law, std::string_view parameter) {
  for (const char* key : law.parameters) {
    if (parameter == key) return true;
  }
  return false;
}

std::string contact_laws_taking(std::string_view parameter) {
  std::string out;
  for (const ContactLawDescriptor& d : contact_law_registry()) {
    if (law_takes(d, parameter)) out += (out.empty() ? "" : "|") + std::string(d.name);
  }
  return out;
}

const char* to_string(ContactLaw law) {
  return descriptor(law).name;
}

std::optional<ContactLaw> contact_law_from_string(const std::string& name) {
  if (const ContactLawDescriptor* d = find_contact_law(name)) return d->law;
  return std::nullopt;
}

std::optional<ParameterError> validate(const ContactTreatment& treatment) {
  for (const ContactLawParameter& p : contact_law_parameters()) {
    if (auto e = p.check(treatment)) return e;
  }
  return std::nullopt;
}

}  // namespace impactid
