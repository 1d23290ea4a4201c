// Reading TOML tables with errors at the bad key: what the scene readers
// (study/plan/scene_file.cpp, study/plan/model_file.cpp) share. Every error goes through a
// TableFail, which throws with the node's position, the dotted key and what is wrong.
#pragma once

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "study/plan/table_fail.hpp"

namespace impactid::toml_reading {

// toml++ keeps a table sorted by key; read in file order so that the first error in the file is
// the one reported.
inline std::vector<std::pair<std::string, const toml::node*>> ordered(const toml::table& table) {
  std::vector<std::pair<std::string, const toml::node*>> entries;
  for (const auto& [key, node] : table) entries.emplace_back(std::string(key.str()), &node);
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    const auto pa = a.second->source().begin, pb = b.second->source().begin;
    return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
  });
  return entries;
}

inline std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

class TableReader {
 public:
  explicit TableReader(const TableFail& fail) : fail_(fail) {}

  [[noreturn]] void fail(const toml::node& node, const std::string& key,
                         const std::string& what) const {
    fail_(node, key, what);
    std::abort();  // fail_ throws; never reached
  }

  double number(const toml::node& node, const std::string& key) const {
    double v = 0.0;
    if (const auto* i = node.as_integer()) {
      v = static_cast<double>(i->get());
    } else if (const auto* f = node.as_floating_point()) {
      v = f->get();
    } else {
      fail(node, key, "must be a number");
    }
    if (!std::isfinite(v)) fail(node, key, "must be finite");
    return v;
  }
  int integer(const toml::node& node, const std::string& key) const {
    const auto* i = node.as_integer();
    if (!i) fail(node, key, "must be an integer");
    if (i->get() < -2'000'000'000 || i->get() > 2'000'000'000) {
      fail(node, key, "must be an integer below 2e9");
    }
    return static_cast<int>(i->get());
  }
  std::string string(const toml::node& node, const std::string& key) const {
    const auto* s = node.as_string();
    if (!s) fail(node, key, "must be a string");
    return s->get();
  }
  const toml::table& table(const toml::node& node, const std::string& key,
                           const std::string& what) const {
    const auto* t = node.as_table();
    if (!t) fail(node, key, what);
    return *t;
  }

 private:
  const TableFail& fail_;
};

}  // namespace impactid::toml_reading
