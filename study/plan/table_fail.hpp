// How the readers of TOML tables (study/plan/toml_reading.hpp and the scene and model readers
// built on it) report a bad value.
#pragma once

#include <toml++/toml.h>

#include <functional>
#include <string>

namespace impactid {

/// Throws, naming the node's position, the dotted key and what is wrong.
using TableFail =
    std::function<void(const toml::node& node, const std::string& key, const std::string& what)>;

}  // namespace impactid
