// The value a plan, the command line or an optimiser gives a parameter: a number, or a name
// (a method, a mass matrix, a contact law, a scene path's primary contact).
#pragma once

#include <string>
#include <variant>

namespace impactid {

using ParameterValue = std::variant<double, std::string>;

}  // namespace impactid
