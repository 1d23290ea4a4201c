// `impactid methods`: every time-stepping method of the registry (core/methods/method_registry.hpp)
// with its summary, the parameters it takes (their defaults, ranges and meaning) and the
// coefficients it derives from them. Text, or --json for scripts, the figures
// (figures/impactid_figures/style.py) and the Python front (impactid.methods_json()).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <ostream>
#include <string>

namespace impactid {

struct MethodDescriptor;

/// How a figure or a report names the method: the head of its summary, the words before the
/// first " (" or " with " ("HHT-alpha", "central difference", "Noh-Bathe explicit"). ASCII like
/// the summary; typography (α for alpha, – between two names) is the figures' business. Read from
/// the summary so that a method's name for people is written once, in its registry entry.
std::string method_label(const MethodDescriptor& method);

/// The registry as `impactid methods --json` prints it: an array of {name, label, summary,
/// parameters [{name, kind, choices, default, description}], derived [names]}, in registry order
/// (the figures give method i of it colour i of their palette).
void write_methods_json(std::ostream& out);

std::function<int()> add_methods_command(CLI::App& app);

}  // namespace impactid
