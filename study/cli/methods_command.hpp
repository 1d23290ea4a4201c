// `impactid methods`: every time-stepping method of the registry (core/methods/method_registry.hpp)
// with its summary, the parameters it takes (their defaults, ranges and meaning) and the
// coefficients it derives from them. Text, or --json for scripts and the Python front.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

std::function<int()> add_methods_command(CLI::App& app);

}  // namespace impactid
