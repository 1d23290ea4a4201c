// `impactid contact-laws`: every contact law of the registry (core/contact/contact_law_registry.hpp)
// with its summary and the parameters it takes (their units, defaults, ranges and meaning). Text,
// or --json for scripts and the figures.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

std::function<int()> add_contact_laws_command(CLI::App& app);

}  // namespace impactid
