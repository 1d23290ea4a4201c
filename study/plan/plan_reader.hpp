// The reader behind load_plan() and load_scene_file() (study/plan/plan.hpp), shared by the files
// that read each study kind: plan.cpp (the root, [scene], [method], [output], [study]'s kind and
// every error message), grid_plan.cpp (grid and list), optimize_plan.cpp, spectral_plan.cpp and
// work_precision_plan.cpp. Only those files include it. Every error is a PlanError naming the
// file, the line and column, the dotted key and its value as written.
#pragma once

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <variant>

#include "core/spectral/amplification.hpp"
#include "metrics/indicator_table.hpp"
#include "study/plan/model_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/plan/scene_file.hpp"
#include "study/plan/scene_path.hpp"
#include "study/plan/work_precision_points.hpp"

namespace impactid::plan_reading {

using namespace std::string_literals;

/// A grid larger than this is taken for a mistake in the plan (a partitions count with a digit
/// too many) rather than a study to start: at milliseconds per point it would run for hours, and
/// load_plan() builds every point (about a second per million) before anything runs.
constexpr long kMaxGridPoints = 1'000'000;
/// Values longer than this are cut in messages.
constexpr std::size_t kMaxValueText = 80;
/// Upper bound of a work-precision study's `repeats`: beyond a few, the minimum no longer moves.
constexpr std::int64_t kMaxRepeats = 100;
/// The study kinds, as plans spell them, for messages.
constexpr const char* kStudyKinds =
    "\"grid\", \"list\", \"optimize\", \"spectral\" or \"work-precision\"";

inline std::string join(const std::vector<std::string>& names, const char* separator = ", ") {
  std::string out;
  for (const std::string& name : names) {
    if (!out.empty()) out += separator;
    out += name;
  }
  return out;
}

inline bool before(toml::source_position a, toml::source_position b) {
  return a.line != b.line ? a.line < b.line : a.column < b.column;
}

struct Entry {
  std::string key;
  const toml::node* node;
};

// toml++ keeps a table sorted by key; plans are read in the order they are written, so that
// axes keep their order and the first error in the file is the one reported.
inline std::vector<Entry> in_file_order(const toml::table& table) {
  std::vector<Entry> entries;
  for (const auto& [key, node] : table) entries.push_back({std::string(key.str()), &node});
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return before(a.node->source().begin, b.node->source().begin);
  });
  return entries;
}

inline std::optional<double> number_of(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

inline std::vector<std::string> parameter_names(ParameterGroup group) {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.group == group) out.push_back(info.name);
  }
  return out;
}

inline std::vector<std::string> numeric_parameter_names() {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.kind != ParameterKind::choice) out.push_back(info.name);
  }
  return out;
}

inline std::vector<std::string> all_parameter_names() {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) out.push_back(info.name);
  return out;
}

inline std::vector<std::string> indicator_names() {
  std::vector<std::string> out;
  for (const IndicatorInfo& info : indicator_table()) out.push_back(info.name);
  return out;
}

inline const char* section_of(ParameterGroup group) {
  switch (group) {
    case ParameterGroup::scene:
      return "scene";
    case ParameterGroup::method:
      return "method";
    case ParameterGroup::output:
      return "output";
  }
  return "";
}

// The key a parameter has in [scene], [method] or [output]: its own name, except the method
// itself, which is [method] name.
inline std::string base_key(const ParameterInfo& info) {
  return std::string(section_of(info.group)) + "." +
         (std::string_view(info.name) == "method" ? "name" : info.name);
}

inline std::string values_text(const std::vector<std::string>& names,
                               const std::vector<double>& values) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) out += ", ";
    out += names[k] + " = " + format_value(values[k]);
  }
  return out;
}

// Reads one plan; every failure throws PlanError "file:line:column: key = value: what".

class PlanReader {
 public:
  PlanReader(const std::string& text, std::string file) : text_(text), file_(std::move(file)) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text_.size(); ++i) {
      if (text_[i] == '\n') line_starts_.push_back(i + 1);
    }
  }

  // A scene file: its root, or its [scene] table, read as a plan's [scene]; build() errors are
  // reported at their keys as for a plan.
  SimulationSettings read_scene_file(const toml::table& root);

  void read(const toml::table& root, Plan& plan);

 private:
  // ---- messages -------------------------------------------------------------------------

  [[noreturn]] void fail_at(const toml::node& where, const std::string& key,
                            const std::string& value, const std::string& what) const;
  [[noreturn]] void fail(const toml::node& node, const std::string& key,
                         const std::string& what) const;
  [[noreturn]] void fail_missing(const toml::node& table, const std::string& key,
                                 const std::string& what) const;
  [[noreturn]] void fail_unknown(const toml::node& node, const std::string& key,
                                 const std::string& context,
                                 const std::vector<std::string>& known) const;

  // Byte offset of a toml++ position (columns count code points), or npos.
  std::size_t offset(toml::source_position p) const;

  // The value as written in the file when it sits on one line (an inline table, an array, a
  // number with its own spelling), else a compact rendering of it.
  std::string written(const toml::node& node) const;

  std::string rendered(const toml::node& node) const;

  // ---- typed reads ------------------------------------------------------------------------

  const toml::table& table(const toml::node& node, const std::string& key,
                           const std::string& what) const;
  std::string string(const toml::node& node, const std::string& key) const;
  double number(const toml::node& node, const std::string& key) const;
  std::int64_t integer(const toml::node& node, const std::string& key) const {
    if (const auto* i = node.as_integer()) return i->get();
    fail(node, key, "must be an integer");
  }

  // A TOML value as a parameter value: integers and floats are numbers, strings stay strings;
  // assign() then checks them against the parameter's kind.
  ParameterValue parameter_value(const toml::node& node, const ParameterInfo& info,
                                 const std::string& key) const;

  void assign_at(SimulationSettings& settings, const ParameterInfo& info, const toml::node& node,
                 const std::string& key) const;

  // ---- sections ---------------------------------------------------------------------------

  void read_root();

  // [scene]: every scene parameter of the settings table, by its own name.
  // A user's model ([scene] kind = "matrices"): its files are relative to the plan's folder.
  void read_model(const toml::table& scene);

  void read_parameters(const toml::table& section, ParameterGroup group, const char* name);

  // [method]: `name` is the method, the other keys its parameters.
  void read_method(const toml::table& section);

  void read_output(const toml::table& section);

  void read_study(const toml::table& study);

  // The base node of a parameter ([scene] length, [method] name, …), or nullptr.
  const toml::node* base_node(const ParameterInfo& info) const;

  // A grid axis or an optimisation parameter: numeric, and not fixed in the base sections too.
  // `choices`: whether a choice parameter may be varied (a grid axis of words).
  const ParameterInfo& varied_parameter(const Entry& e, const std::string& key, const char* what,
                                        bool choices = false) const;

  // A dotted key of the scene of bodies (study/plan/scene_path.hpp) as an axis or a parameter: it
  // must name a number of the plan's [[scene.body]] scene. Elements are the one integer among them.
  const ParameterInfo& varied_scene_path(const Entry& e, const std::string& key,
                                         const char* what) const;

  void read_grid(const toml::table& study);

  // { from, to, partitions } (Dakota's convention: k partitions, k + 1 values) or { values }.
  // `{ values = [..] }` of an axis: numbers, at least one, none twice (and each > 0 when
  // `positive`), each error at its item.
  std::vector<double> listed_values(const toml::node& values, const std::string& values_key,
                                    bool positive = false) const;
  std::vector<double> axis_values(const toml::table& axis, const std::string& key) const;
  // A choice axis, `{ values = ["word", …] }`: its words, each checked against the parameter.
  std::vector<std::string> choice_axis_labels(const toml::table& axis, const std::string& key,
                                              const ParameterInfo& info) const;

  void read_list(const toml::table& study);

  void read_optimize(const toml::table& study);

  // "eps_p", or { eps_p = 1.0, nop_p = 0.01 }.
  std::vector<std::pair<std::string, double>> objective(const toml::node& node,
                                                        const std::string& key) const;

  std::vector<IndicatorConstraint> constraints(const toml::table& t) const;

  // [study.practical]: indicator = maximum, or indicator = { max = .., min = .. }. Every
  // indicator is >= 0 by definition, so a negative bound is a mistake, not a filter.
  std::vector<IndicatorConstraint> practical(const toml::node& node) const;

  // ---- kind = "spectral" ------------------------------------------------------------------

  void read_spectral(const toml::table& study);

  // { from, to, points }: `points` values spaced evenly in log(Ω), both ends included (the last
  // exactly `to`); or { values = [..] }. Every value > 0.
  std::vector<double> log_axis_values(const toml::node& node, const std::string& key) const;

  // methods = [{ method = "newmark", delta = 0.3 }, ..]: each a method and its parameters, by
  // the names of [method] (with `method` for the name, as in list points), built by build().
  std::vector<SpectralMethod> spectral_methods(const toml::node& node,
                                               const std::string& key) const;

  // A spectral study runs no simulation: [scene] and [method] would be ignored, so they are
  // errors; of [output] only `file` applies.
  void check_spectral_sections() const;

  // ---- kind = "work-precision" ------------------------------------------------------------

  void read_work_precision(const toml::table& study);

  // elements = [50, 100] or courant = [0.5, 1.0]: a non-empty array of numbers, each > 0 and
  // finite, no value twice; element counts must be integers.
  std::vector<double> number_list(const toml::node& node, const std::string& key,
                                  const char* what) const;

  // The methods this project recommends (docs/methods.md, "Decisions and findings"; the spectral
  // plan's set): what a work-precision study compares unless the plan lists its own.
  static std::vector<SpectralMethod> default_work_precision_methods();

  // The study sets the method, the mesh and the step: [method] would be ignored, and so would
  // [scene] elements, courant and dt; [output] indicators and histories do not apply (the
  // columns are fixed, no histories are kept).
  void check_work_precision_sections() const;

  // Every point built on [scene] (a scene may be valid at one mesh and not another: t_end
  // shorter than a step, say); an error names the first bad point.
  void check_work_precision() const;

  // ---- checks across parameters -----------------------------------------------------------

  // Where a build() error about `field` is reported when the study does not vary it: its key
  // in [scene], [method] or [output] if written there, else the section (or the file start).
  [[noreturn]] void fail_base(const ParameterError& error, const std::string& suffix) const;

  std::set<std::string> varied_names() const;

  // The base on its own, so that a wrong fixed value is reported at its key once rather than
  // at the first point. Errors about a parameter the study varies (or with the method varied
  // by a list) are left to the points, where the varied values are known.
  void check_base() const;

  void check_points() const;

  // Every optimisation parameter is built at the start point and at each of its bounds (the
  // others at their start): the settings' rules are per parameter, so a box that passes these
  // holds no point that build() rejects.
  void check_optimize() const;

  struct ParameterNodes {
    const toml::node *table, *from, *to, *start;
  };

  const std::string& text_;
  std::string file_;
  std::vector<std::size_t> line_starts_;
  const toml::node* histories_node_ = nullptr;  // for a message that needs the study kind
  // work-precision keys, where a point's error is reported (nullptr: the default was used)
  const toml::node *methods_node_ = nullptr, *elements_node_ = nullptr, *courant_node_ = nullptr;
  const toml::table* root_ = nullptr;
  Plan* plan_ = nullptr;
  const toml::array* points_ = nullptr;
  std::map<std::string, const toml::node*> axis_nodes_;
  std::map<std::string, ParameterNodes> parameter_nodes_;
};

}  // namespace impactid::plan_reading
