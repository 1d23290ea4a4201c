#include "study/plan.hpp"

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

#include "core/amplification.hpp"
#include "study/indicator_table.hpp"
#include "study/model_file.hpp"
#include "study/point_set.hpp"
#include "study/scene_file.hpp"
#include "study/scene_path.hpp"
#include "study/work_precision.hpp"

namespace impactid {
namespace {

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

struct Algorithm {
  const char* name;   ///< as written in a plan
  const char* nlopt;  ///< NLopt's name
};
constexpr std::array<Algorithm, 20> kAlgorithms{{
    {"GN_DIRECT", "GN_DIRECT"},
    {"GN_DIRECT_L", "GN_DIRECT_L"},
    {"GN_ORIG_DIRECT", "GN_ORIG_DIRECT"},
    {"GN_ORIG_DIRECT_L", "GN_ORIG_DIRECT_L"},
    {"GN_CRS2_LM", "GN_CRS2_LM"},
    {"GN_ISRES", "GN_ISRES"},
    {"GN_ESCH", "GN_ESCH"},
    {"LN_COBYLA", "LN_COBYLA"},
    {"LN_BOBYQA", "LN_BOBYQA"},
    {"LN_NELDERMEAD", "LN_NELDERMEAD"},
    {"LN_SBPLX", "LN_SBPLX"},
    {"LN_PRAXIS", "LN_PRAXIS"},
    {"DIRECT", "GN_DIRECT_L"},
    {"CRS2", "GN_CRS2_LM"},
    {"ISRES", "GN_ISRES"},
    {"COBYLA", "LN_COBYLA"},
    {"BOBYQA", "LN_BOBYQA"},
    {"NELDERMEAD", "LN_NELDERMEAD"},
    {"NELDER-MEAD", "LN_NELDERMEAD"},
    {"SBPLX", "LN_SBPLX"},
}};

std::string join(const std::vector<std::string>& names, const char* separator = ", ") {
  std::string out;
  for (const std::string& name : names) {
    if (!out.empty()) out += separator;
    out += name;
  }
  return out;
}

bool before(toml::source_position a, toml::source_position b) {
  return a.line != b.line ? a.line < b.line : a.column < b.column;
}

struct Entry {
  std::string key;
  const toml::node* node;
};

// toml++ keeps a table sorted by key; plans are read in the order they are written, so that
// axes keep their order and the first error in the file is the one reported.
std::vector<Entry> in_file_order(const toml::table& table) {
  std::vector<Entry> entries;
  for (const auto& [key, node] : table) entries.push_back({std::string(key.str()), &node});
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return before(a.node->source().begin, b.node->source().begin);
  });
  return entries;
}

std::optional<double> number_of(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point()) return f->get();
  return std::nullopt;
}

std::vector<std::string> parameter_names(ParameterGroup group) {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.group == group) out.push_back(info.name);
  }
  return out;
}

std::vector<std::string> numeric_parameter_names() {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) {
    if (info.kind != ParameterKind::choice) out.push_back(info.name);
  }
  return out;
}

std::vector<std::string> all_parameter_names() {
  std::vector<std::string> out;
  for (const ParameterInfo& info : parameter_table()) out.push_back(info.name);
  return out;
}

std::vector<std::string> indicator_names() {
  std::vector<std::string> out;
  for (const IndicatorInfo& info : indicator_table()) out.push_back(info.name);
  return out;
}

const char* section_of(ParameterGroup group) {
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
std::string base_key(const ParameterInfo& info) {
  return std::string(section_of(info.group)) + "." +
         (std::string_view(info.name) == "method" ? "name" : info.name);
}

std::string values_text(const std::vector<std::string>& names, const std::vector<double>& values) {
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
  SimulationSettings read_scene_file(const toml::table& root) {
    Plan plan;
    root_ = &root;
    plan_ = &plan;
    // With a [scene] table the file may be a plan: its scene is taken, its study is not run.
    const toml::node* scene_node = root.get("scene");
    const toml::table& scene =
        scene_node ? table(*scene_node, "scene", "must be a table ([scene])") : root;
    if (is_scene_of_bodies(scene)) {
      plan.base.bodies =
          read_scene_of_bodies(scene, "scene",
                               [this](const toml::node& at, const std::string& key,
                                      const std::string& what) { fail(at, key, what); });
    }
    read_model(scene);
    toml::table parameters;  // the whole-scene keys; name and description are the file's
    for (const auto& [key, node] : scene) {
      if (!scene_node && (key == "name" || key == "description")) continue;
      parameters.insert(key, node);
    }
    read_parameters(scene_node ? scene : parameters, ParameterGroup::scene, "scene");
    const auto built = build(plan.base);
    if (const auto* error = std::get_if<ParameterError>(&built)) fail_base(*error, "");
    return plan.base;
  }

  void read(const toml::table& root, Plan& plan) {
    root_ = &root;
    plan_ = &plan;
    read_root();
    check_base();
    check_points();
    if (plan.output.file.empty()) plan.output.file = "results/" + plan.name + ".h5";
    if (plan.output.indicators.empty()) plan.output.indicators = indicator_names();
  }

 private:
  // ---- messages -------------------------------------------------------------------------

  [[noreturn]] void fail_at(const toml::node& where, const std::string& key,
                            const std::string& value, const std::string& what) const {
    const toml::source_position p = where.source().begin;
    throw PlanError(file_ + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": " +
                    key + " = " + value + ": " + what);
  }
  [[noreturn]] void fail(const toml::node& node, const std::string& key,
                         const std::string& what) const {
    fail_at(node, key, written(node), what);
  }
  [[noreturn]] void fail_missing(const toml::node& table, const std::string& key,
                                 const std::string& what) const {
    fail_at(table, key, "(missing)", what);
  }
  [[noreturn]] void fail_unknown(const toml::node& node, const std::string& key,
                                 const std::string& context,
                                 const std::vector<std::string>& known) const {
    fail(node, key, "unknown key (" + context + ": " + join(known) + ")");
  }

  // Byte offset of a toml++ position (columns count code points), or npos.
  std::size_t offset(toml::source_position p) const {
    if (p.line == 0 || p.line > line_starts_.size() || p.column == 0) return std::string::npos;
    std::size_t i = line_starts_[p.line - 1];
    for (toml::source_index c = 1; c < p.column; ++c) {
      if (i >= text_.size() || text_[i] == '\n') return std::string::npos;
      ++i;
      while (i < text_.size() && (static_cast<unsigned char>(text_[i]) & 0xC0) == 0x80) ++i;
    }
    return i;
  }

  // The value as written in the file when it sits on one line (an inline table, an array, a
  // number with its own spelling), else a compact rendering of it.
  std::string written(const toml::node& node) const {
    const toml::source_region& r = node.source();
    const bool header_table = node.is_table() && !node.as_table()->is_inline();
    const bool table_array = node.is_array_of_tables() && !node.as_array()->empty() &&
                             node.as_array()->front().is_table() &&
                             !node.as_array()->front().as_table()->is_inline();
    std::string out;
    if (!header_table && !table_array && r.begin.line == r.end.line) {
      const std::size_t b = offset(r.begin), e = offset(r.end);
      if (b != std::string::npos && e != std::string::npos && e > b) out = text_.substr(b, e - b);
    }
    if (out.empty()) out = rendered(node);
    if (out.size() > kMaxValueText) out = out.substr(0, kMaxValueText - 3) + "...";
    return out;
  }

  std::string rendered(const toml::node& node) const {
    if (const auto* s = node.as_string()) {
      std::string out = "\"";
      for (const char c : s->get()) {
        if (c == '"' || c == '\\') out += '\\';
        if (c == '\n') {
          out += "\\n";
        } else {
          out += c;
        }
      }
      return out + "\"";
    }
    if (const auto* i = node.as_integer()) return std::to_string(i->get());
    if (const auto* f = node.as_floating_point()) return format_value(f->get());
    if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* t = node.as_table()) {
      std::string out = "{";
      for (const Entry& e : in_file_order(*t)) {
        out += (out.size() > 1 ? ", " : " ") + e.key + " = " + written(*e.node);
      }
      return out + (out.size() > 1 ? " }" : "}");
    }
    if (const auto* a = node.as_array()) {
      std::string out = "[";
      for (const toml::node& e : *a) out += (out.size() > 1 ? ", " : " ") + written(e);
      return out + (out.size() > 1 ? " ]" : "]");
    }
    const toml::source_region& r = node.source();  // dates and times: one line
    const std::size_t b = offset(r.begin), e = offset(r.end);
    return b != std::string::npos && e != std::string::npos && e > b ? text_.substr(b, e - b)
                                                                     : "(value)";
  }

  // ---- typed reads ------------------------------------------------------------------------

  const toml::table& table(const toml::node& node, const std::string& key,
                           const std::string& what) const {
    if (const auto* t = node.as_table()) return *t;
    fail(node, key, what);
  }
  std::string string(const toml::node& node, const std::string& key) const {
    if (const auto* s = node.as_string()) return s->get();
    fail(node, key, "must be a string");
  }
  double number(const toml::node& node, const std::string& key) const {
    const auto v = number_of(node);
    if (!v) fail(node, key, "must be a number");
    if (!std::isfinite(*v)) fail(node, key, "must be finite");
    return *v;
  }
  std::int64_t integer(const toml::node& node, const std::string& key) const {
    if (const auto* i = node.as_integer()) return i->get();
    fail(node, key, "must be an integer");
  }

  // A TOML value as a parameter value: integers and floats are numbers, strings stay strings;
  // assign() then checks them against the parameter's kind.
  ParameterValue parameter_value(const toml::node& node, const ParameterInfo& info,
                                 const std::string& key) const {
    if (const auto v = number_of(node)) return *v;
    if (const auto* s = node.as_string()) return s->get();
    if (info.kind == ParameterKind::choice) {
      fail(node, key, "must be a string, one of "s + info.choices);
    }
    fail(node, key,
         info.kind == ParameterKind::integer ? "must be an integer" : "must be a number");
  }

  void assign_at(SimulationSettings& settings, const ParameterInfo& info, const toml::node& node,
                 const std::string& key) const {
    if (auto error = assign(settings, info.name, parameter_value(node, info, key))) {
      fail(node, key, error->constraint);
    }
  }

  // ---- sections ---------------------------------------------------------------------------

  void read_root() {
    const std::vector<std::string> known{"name",   "description", "scene",
                                         "method", "study",       "output"};
    const toml::node* study = nullptr;
    for (const Entry& e : in_file_order(*root_)) {
      const toml::node& node = *e.node;
      if (e.key == "name") {
        plan_->name = string(node, e.key);
        if (plan_->name.empty()) fail(node, e.key, "must not be empty");
        if (plan_->name.find_first_of("/\\") != std::string::npos) {
          fail(node, e.key, "must not contain '/' or '\\' (it names the default output file)");
        }
      } else if (e.key == "description") {
        plan_->description = string(node, e.key);
      } else if (e.key == "scene" && node.is_string()) {
        // `scene = "FILE.toml"`: a scene file of its own (a model's, with its many contacts),
        // relative to the plan.
        const std::filesystem::path path =
            std::filesystem::path(file_).parent_path() / node.as_string()->get();
        try {
          plan_->base = load_scene_file(path);
        } catch (const PlanError& error) {
          fail(node, e.key, error.what());
        }
      } else if (e.key == "scene") {
        const toml::table& scene =
            table(node, e.key, "must be a table ([scene]) or the name of a scene file");
        if (is_scene_of_bodies(scene)) {
          plan_->base.bodies =
              read_scene_of_bodies(scene, "scene",
                                   [this](const toml::node& at, const std::string& key,
                                          const std::string& what) { fail(at, key, what); });
        }
        read_model(scene);
        read_parameters(scene, ParameterGroup::scene, "scene");
      } else if (e.key == "method") {
        read_method(table(node, e.key, "must be a table ([method])"));
      } else if (e.key == "study") {
        study = &node;
      } else if (e.key == "output") {
        read_output(table(node, e.key, "must be a table ([output])"));
      } else {
        fail_unknown(node, e.key, "top-level keys", known);
      }
    }
    if (!study) {
      fail_missing(*root_, "study", "a plan needs a [study] table with kind = "s + kStudyKinds);
    }
    read_study(table(*study, "study", "must be a table ([study])"));
    if (plan_->kind == StudyKind::spectral) check_spectral_sections();
    if (plan_->kind == StudyKind::work_precision) check_work_precision_sections();
    if (histories_node_ && plan_->kind == StudyKind::optimize) {
      fail(*histories_node_, "output.histories",
           "time histories are written for grid and list points, not for an optimisation");
    }
  }

  // [scene]: every scene parameter of the settings table, by its own name.
  // A user's model ([scene] kind = "matrices"): its files are relative to the plan's folder.
  void read_model(const toml::table& scene) {
    if (const toml::node* kind = scene.get("kind")) {
      if (!is_model_scene(scene)) {
        fail(*kind, "scene.kind",
             "is not a kind of scene: \"matrices\" (a user's model) is the one kind given by "
             "name; the rod and scenes of bodies need no kind");
      }
      if (is_scene_of_bodies(scene)) {
        fail(*kind, "scene.kind",
             "a model cannot have bodies or walls ([[scene.body]], [scene.wall])");
      }
      plan_->base.model =
          read_model_scene(scene, "scene", std::filesystem::path(file_).parent_path(),
                           [this](const toml::node& at, const std::string& key,
                                  const std::string& what) { fail(at, key, what); });
    }
  }

  void read_parameters(const toml::table& section, ParameterGroup group, const char* name) {
    for (const Entry& e : in_file_order(section)) {
      const std::string key = name + "."s + e.key;
      if (group == ParameterGroup::scene && plan_->base.bodies && is_scene_of_bodies_key(e.key)) {
        continue;  // read by read_scene_of_bodies
      }
      if (group == ParameterGroup::scene && plan_->base.model && is_model_scene_key(e.key)) {
        continue;  // read by read_model_scene
      }
      const ParameterInfo* info = find_parameter(e.key);
      if (!info || info->group != group) {
        fail_unknown(*e.node, key, name + " keys"s, parameter_names(group));
      }
      assign_at(plan_->base, *info, *e.node, key);
    }
  }

  // [method]: `name` is the method, the other keys its parameters.
  void read_method(const toml::table& section) {
    std::vector<std::string> known{"name"};
    for (const ParameterInfo& info : parameter_table()) {
      if (info.group == ParameterGroup::method && std::string_view(info.name) != "method") {
        known.push_back(info.name);
      }
    }
    for (const Entry& e : in_file_order(section)) {
      const std::string key = "method." + e.key;
      const ParameterInfo* info = find_parameter(e.key == "name" ? "method" : e.key);
      if (!info || info->group != ParameterGroup::method || e.key == "method") {
        fail_unknown(*e.node, key, "method keys", known);
      }
      assign_at(plan_->base, *info, *e.node, key);
    }
  }

  void read_output(const toml::table& section) {
    std::vector<std::string> known{"file", "indicators", "checkpoint_seconds", "histories"};
    for (const std::string& name : parameter_names(ParameterGroup::output)) known.push_back(name);
    for (const Entry& e : in_file_order(section)) {
      const std::string key = "output." + e.key;
      const toml::node& node = *e.node;
      if (e.key == "file") {
        const std::string file = string(node, key);
        if (file.empty()) fail(node, key, "must not be empty");
        plan_->output.file = file;
      } else if (e.key == "indicators") {
        const auto* array = node.as_array();
        if (!array) fail(node, key, "must be an array of indicator names");
        if (array->empty()) fail(node, key, "must name at least one indicator");
        std::vector<std::string> names;
        for (std::size_t k = 0; k < array->size(); ++k) {
          const toml::node& item = *array->get(k);
          const std::string item_key = key + "[" + std::to_string(k) + "]";
          const std::string name = string(item, item_key);
          if (!find_indicator(name)) {
            fail(item, item_key, "unknown indicator (indicators: " + join(indicator_names()) + ")");
          }
          if (std::find(names.begin(), names.end(), name) != names.end()) {
            fail(item, item_key, "is listed twice");
          }
          names.push_back(name);
        }
        plan_->output.indicators = names;
      } else if (e.key == "histories") {
        const std::string folder = string(node, key);
        if (folder.empty()) fail(node, key, "must not be empty");
        plan_->output.histories = folder;
        histories_node_ = &node;
      } else if (e.key == "checkpoint_seconds") {
        const double v = number(node, key);
        if (!(v > 0.0)) fail(node, key, "must be > 0");
        plan_->output.checkpoint_seconds = v;
      } else if (const ParameterInfo* info = find_parameter(e.key);
                 info && info->group == ParameterGroup::output) {
        assign_at(plan_->base, *info, node, key);
      } else {
        fail_unknown(node, key, "output keys", known);
      }
    }
  }

  void read_study(const toml::table& study) {
    const toml::node* kind = study.get("kind");
    if (!kind) fail_missing(study, "study.kind", "must be "s + kStudyKinds);
    const std::string text = string(*kind, "study.kind");
    if (text == "grid") {
      plan_->kind = StudyKind::grid;
    } else if (text == "list") {
      plan_->kind = StudyKind::list;
    } else if (text == "optimize") {
      plan_->kind = StudyKind::optimize;
    } else if (text == "spectral") {
      plan_->kind = StudyKind::spectral;
    } else if (text == "work-precision") {
      plan_->kind = StudyKind::work_precision;
    } else {
      fail(*kind, "study.kind", "must be "s + kStudyKinds);
    }

    switch (plan_->kind) {
      case StudyKind::grid:
        read_grid(study);
        break;
      case StudyKind::list:
        read_list(study);
        break;
      case StudyKind::optimize:
        read_optimize(study);
        break;
      case StudyKind::spectral:
        read_spectral(study);
        break;
      case StudyKind::work_precision:
        read_work_precision(study);
        break;
    }
  }

  // The base node of a parameter ([scene] length, [method] name, …), or nullptr.
  const toml::node* base_node(const ParameterInfo& info) const {
    const toml::node* section = root_->get(section_of(info.group));
    if (!section || !section->is_table()) return nullptr;
    return section->as_table()->get(std::string_view(info.name) == "method" ? "name" : info.name);
  }

  // A grid axis or an optimisation parameter: numeric, and not fixed in the base sections too.
  const ParameterInfo& varied_parameter(const Entry& e, const std::string& key,
                                        const char* what) const {
    if (is_scene_path(e.key)) return varied_scene_path(e, key, what);
    const ParameterInfo* info = find_parameter(e.key);
    if (!info) {
      fail(*e.node, key,
           "is not a parameter (numeric parameters: " + join(numeric_parameter_names()) + ")");
    }
    if (info->kind == ParameterKind::choice) {
      fail(*e.node, key,
           "is a choice parameter ("s + info->choices + "): only numeric parameters can be " +
               what + "; vary choices in a list study");
    }
    if (base_node(*info)) {
      fail(*e.node, key,
           "is also set as " + base_key(*info) + ": a parameter is either fixed or " + what);
    }
    return *info;
  }

  // A dotted key of the scene of bodies (study/scene_path.hpp) as an axis or a parameter: it must
  // name a number of the plan's [[scene.body]] scene. Elements are the one integer among them.
  const ParameterInfo& varied_scene_path(const Entry& e, const std::string& key,
                                         const char* what) const {
    static constexpr ParameterInfo kReal{"(scene key)",
                                         ParameterGroup::scene,
                                         ParameterKind::real,
                                         "",
                                         "a key of the scene of bodies",
                                         "",
                                         ""};
    static constexpr ParameterInfo kInteger{"(scene key)",
                                            ParameterGroup::scene,
                                            ParameterKind::integer,
                                            "",
                                            "a key of the scene of bodies",
                                            "",
                                            ""};
    if (!plan_->base.bodies) {
      fail(*e.node, key,
           "is a key of a scene of bodies, and [scene] has no [[scene.body]] tables (the "
           "one-body rod's keys are length, elements, velocity, gap, ...)");
    }
    if (e.key == "primary_contact") {
      fail(*e.node, key, "is a choice (a contact's name): only numbers can be "s + what);
    }
    Scene probe = *plan_->base.bodies;
    if (auto error = assign_scene_path(probe, e.key, 1.0)) fail(*e.node, key, error->constraint);
    return e.key.ends_with(".elements") ? kInteger : kReal;
  }

  void read_grid(const toml::table& study) {
    const toml::node* axes_node = nullptr;
    for (const Entry& e : in_file_order(study)) {
      if (e.key == "axes") {
        axes_node = e.node;
      } else if (e.key == "practical") {
        plan_->practical = practical(*e.node);
      } else if (e.key != "kind") {
        fail_unknown(*e.node, "study." + e.key, "grid keys", {"kind", "axes", "practical"});
      }
    }
    if (!axes_node) fail_missing(study, "study.axes", "a grid study needs a table [study.axes]");
    const toml::table& axes = table(*axes_node, "study.axes", "must be a table of axes");

    std::vector<const Entry*> coupled;
    const std::vector<Entry> entries = in_file_order(axes);
    for (const Entry& e : entries) {
      const std::string key = "study.axes." + e.key;
      varied_parameter(e, key, "a grid axis");
      axis_nodes_[e.key] = e.node;
      if (e.node->is_string()) {
        coupled.push_back(&e);
      } else if (const auto* t = e.node->as_table()) {
        plan_->axes.push_back({e.key, axis_values(*t, key)});
      } else {
        fail(*e.node, key,
             "must be { from = .., to = .., partitions = .. }, { values = [..] } or a "
             "coupled-axis expression such as \"-1.5*alpha\"");
      }
    }
    if (plan_->axes.empty()) {
      fail(*axes_node, "study.axes", "a grid needs at least one independent axis");
    }
    long size = 1;
    for (const GridAxis& axis : plan_->axes) {
      size *= static_cast<long>(axis.values.size());  // each <= kMaxGridPoints: no overflow
      if (size > kMaxGridPoints) {
        fail(*axes_node, "study.axes",
             "the grid has more than " + std::to_string(kMaxGridPoints) +
                 " points; split the study");
      }
    }

    std::vector<std::string> independent;
    for (const GridAxis& axis : plan_->axes) independent.push_back(axis.name);
    for (const Entry* e : coupled) {
      const std::string key = "study.axes." + e->key;
      std::string error;
      auto expression = AxisExpression::parse(e->node->as_string()->get(), error);
      if (!expression) fail(*e->node, key, "invalid expression: " + error);
      for (const std::string& name : expression->variables()) {
        if (std::find(independent.begin(), independent.end(), name) != independent.end()) continue;
        const bool is_coupled = std::any_of(coupled.begin(), coupled.end(),
                                            [&](const Entry* c) { return c->key == name; });
        fail(*e->node, key,
             is_coupled ? "uses '" + name +
                              "', a coupled axis: an expression may use only "
                              "independent axes (" +
                              join(independent) + ")"
                        : "uses '" + name + "', which is not an axis (independent axes: " +
                              join(independent) + ")");
      }
      plan_->coupled.push_back({e->key, std::move(*expression)});
    }
  }

  // { from, to, partitions } (Dakota's convention: k partitions, k + 1 values) or { values }.
  std::vector<double> axis_values(const toml::table& axis, const std::string& key) const {
    const toml::node *from = nullptr, *to = nullptr, *partitions = nullptr, *values = nullptr;
    for (const Entry& e : in_file_order(axis)) {
      if (e.key == "from") {
        from = e.node;
      } else if (e.key == "to") {
        to = e.node;
      } else if (e.key == "partitions") {
        partitions = e.node;
      } else if (e.key == "values") {
        values = e.node;
      } else {
        fail_unknown(*e.node, key + "." + e.key, "axis keys",
                     {"from", "to", "partitions", "values"});
      }
    }
    if (values) {
      if (from || to || partitions) {
        fail(axis, key, "give either values or from, to and partitions, not both");
      }
      const auto* array = values->as_array();
      const std::string values_key = key + ".values";
      if (!array) fail(*values, values_key, "must be an array of numbers");
      if (array->empty()) fail(*values, values_key, "must hold at least one value");
      if (array->size() > static_cast<std::size_t>(kMaxGridPoints)) {
        fail(*values, values_key, "holds more than " + std::to_string(kMaxGridPoints) + " values");
      }
      std::vector<double> out;
      for (std::size_t k = 0; k < array->size(); ++k) {
        const std::string item_key = values_key + "[" + std::to_string(k) + "]";
        const double v = number(*array->get(k), item_key);
        if (std::find(out.begin(), out.end(), v) != out.end()) {
          fail(*array->get(k), item_key, "repeats an earlier value");
        }
        out.push_back(v);
      }
      return out;
    }
    if (!from) {
      fail_missing(axis, key + ".from", "an axis needs from, to and partitions, or values");
    }
    if (!to) fail_missing(axis, key + ".to", "an axis needs from, to and partitions, or values");
    if (!partitions) {
      fail_missing(axis, key + ".partitions",
                   "an axis needs partitions (k partitions give k + 1 values), or values");
    }
    const double lo = number(*from, key + ".from");
    const double hi = number(*to, key + ".to");
    const std::int64_t k = integer(*partitions, key + ".partitions");
    if (k < 1) fail(*partitions, key + ".partitions", "must be >= 1");
    if (k >= kMaxGridPoints) {
      fail(*partitions, key + ".partitions", "must be < " + std::to_string(kMaxGridPoints));
    }
    if (lo == hi) fail(*to, key + ".to", "equals from; use values = [..] for a single value");
    std::vector<double> out(static_cast<std::size_t>(k) + 1);
    for (std::int64_t i = 0; i < k; ++i) {
      out[static_cast<std::size_t>(i)] =
          lo + static_cast<double>(i) * (hi - lo) / static_cast<double>(k);
    }
    out.back() = hi;  // exactly as written, whatever the rounding above
    return out;
  }

  void read_list(const toml::table& study) {
    const toml::node* points_node = nullptr;
    for (const Entry& e : in_file_order(study)) {
      if (e.key == "points") {
        points_node = e.node;
      } else if (e.key == "practical") {
        plan_->practical = practical(*e.node);
      } else if (e.key != "kind") {
        fail_unknown(*e.node, "study." + e.key, "list keys", {"kind", "points", "practical"});
      }
    }
    if (!points_node) {
      fail_missing(study, "study.points",
                   "a list study needs points = [{ .. }, ..] or [[study.points]] tables");
    }
    const auto* array = points_node->as_array();
    if (!array) fail(*points_node, "study.points", "must be an array of tables");
    if (array->empty()) fail(*points_node, "study.points", "must hold at least one point");
    points_ = array;
    for (std::size_t k = 0; k < array->size(); ++k) {
      const std::string point_key = "study.points[" + std::to_string(k) + "]";
      const toml::table& point =
          table(*array->get(k), point_key, "must be a table of parameter = value");
      // Checked one key at a time so that a wrong value is reported where it is written; the
      // rules across parameters are checked per point in check_points().
      SimulationSettings scratch = plan_->base;
      ListPoint values;
      for (const Entry& e : in_file_order(point)) {
        const std::string key = point_key + "." + e.key;
        const ParameterInfo* info = is_scene_path(e.key)
                                        ? &varied_scene_path(e, key, "set at a point")
                                        : find_parameter(e.key);
        if (!info) fail_unknown(*e.node, key, "point keys are parameters", all_parameter_names());
        const ParameterValue value = parameter_value(*e.node, *info, key);
        if (auto error = assign(scratch, e.key, value)) fail(*e.node, key, error->constraint);
        values.emplace_back(e.key, value);
      }
      plan_->points.push_back(std::move(values));
    }
  }

  void read_optimize(const toml::table& study) {
    OptimizeStudy& out = plan_->optimize;
    const std::vector<std::string> known{"kind",       "algorithm", "objective", "max_evaluations",
                                         "xtol_rel",   "ftol_rel",  "seed",      "parameters",
                                         "constraints"};
    const toml::node* parameters = nullptr;
    for (const Entry& e : in_file_order(study)) {
      const std::string key = "study." + e.key;
      const toml::node& node = *e.node;
      if (e.key == "kind") {
      } else if (e.key == "algorithm") {
        const std::string name = string(node, key);
        const auto it = std::find_if(kAlgorithms.begin(), kAlgorithms.end(),
                                     [&](const Algorithm& a) { return name == a.name; });
        if (it == kAlgorithms.end()) {
          std::vector<std::string> names;
          for (const Algorithm& a : kAlgorithms) names.push_back(a.name);
          fail(node, key, "unknown algorithm (algorithms: " + join(names) + ")");
        }
        out.algorithm = it->nlopt;
      } else if (e.key == "objective") {
        out.objective = objective(node, key);
      } else if (e.key == "max_evaluations") {
        const std::int64_t v = integer(node, key);
        if (v < 1 || v > std::numeric_limits<int>::max()) {
          fail(node, key,
               "must lie in [1, " + std::to_string(std::numeric_limits<int>::max()) + "]");
        }
        out.max_evaluations = static_cast<long>(v);
      } else if (e.key == "xtol_rel" || e.key == "ftol_rel") {
        const double v = number(node, key);
        if (!(v >= 0.0)) fail(node, key, "must be >= 0");
        (e.key == "xtol_rel" ? out.xtol_rel : out.ftol_rel) = v;
      } else if (e.key == "seed") {
        const std::int64_t v = integer(node, key);
        if (v < 0 || v > std::numeric_limits<unsigned>::max()) {
          fail(node, key,
               "must lie in [0, " + std::to_string(std::numeric_limits<unsigned>::max()) + "]");
        }
        out.seed = static_cast<unsigned>(v);
      } else if (e.key == "parameters") {
        parameters = &node;
      } else if (e.key == "constraints") {
        out.constraints =
            constraints(table(node, key, "must be a table of indicator = { max, min }"));
      } else if (e.key == "practical") {
        fail(node, key,
             "is for grid and list studies; an optimisation states its limits as "
             "[study.constraints]");
      } else {
        fail_unknown(node, key, "optimize keys", known);
      }
    }
    if (!parameters) {
      fail_missing(study, "study.parameters",
                   "an optimize study needs a table [study.parameters] of name = { from, to }");
    }
    const toml::table& table_ =
        table(*parameters, "study.parameters", "must be a table of name = { from, to, start }");
    for (const Entry& e : in_file_order(table_)) {
      const std::string key = "study.parameters." + e.key;
      const ParameterInfo& info = varied_parameter(e, key, "an optimisation parameter");
      if (info.kind == ParameterKind::integer) {
        fail(*e.node, key,
             "is an integer parameter: NLopt varies parameters continuously; vary it "
             "in a grid or list study");
      }
      const toml::table& p = table(*e.node, key, "must be { from = .., to = .., start = .. }");
      const toml::node *from = nullptr, *to = nullptr, *start = nullptr;
      for (const Entry& f : in_file_order(p)) {
        if (f.key == "from") {
          from = f.node;
        } else if (f.key == "to") {
          to = f.node;
        } else if (f.key == "start") {
          start = f.node;
        } else {
          fail_unknown(*f.node, key + "." + f.key, "parameter keys", {"from", "to", "start"});
        }
      }
      if (!from) fail_missing(p, key + ".from", "a parameter needs bounds from and to");
      if (!to) fail_missing(p, key + ".to", "a parameter needs bounds from and to");
      OptimizeParameter parameter{e.key, number(*from, key + ".from"), number(*to, key + ".to"),
                                  std::nullopt};
      if (!(parameter.lower < parameter.upper)) fail(*to, key + ".to", "must be > from");
      if (start) {
        const double s = number(*start, key + ".start");
        if (!(s >= parameter.lower && s <= parameter.upper)) {
          fail(*start, key + ".start", "must lie in [from, to]");
        }
        parameter.start = s;
      }
      parameter_nodes_[e.key] = {e.node, from, to, start};
      out.parameters.push_back(parameter);
    }
    if (out.parameters.empty()) {
      fail(*parameters, "study.parameters", "must name at least one parameter");
    }
  }

  // "eps_p", or { eps_p = 1.0, nop_p = 0.01 }.
  std::vector<std::pair<std::string, double>> objective(const toml::node& node,
                                                        const std::string& key) const {
    const auto check = [&](const toml::node& where, const std::string& where_key,
                           const std::string& name) {
      if (!find_indicator(name)) {
        fail(where, where_key, "unknown indicator (indicators: " + join(indicator_names()) + ")");
      }
    };
    if (const auto* s = node.as_string()) {
      check(node, key, s->get());
      return {{s->get(), 1.0}};
    }
    const auto* t = node.as_table();
    if (!t) fail(node, key, "must be an indicator name or a table of indicator = weight");
    std::vector<std::pair<std::string, double>> out;
    for (const Entry& e : in_file_order(*t)) {
      const std::string weight_key = key + "." + e.key;
      check(*e.node, weight_key, e.key);
      const double w = number(*e.node, weight_key);
      if (w == 0.0) fail(*e.node, weight_key, "must not be 0 (leave the indicator out)");
      out.emplace_back(e.key, w);
    }
    if (out.empty()) fail(node, key, "must name at least one indicator");
    return out;
  }

  std::vector<IndicatorConstraint> constraints(const toml::table& t) const {
    std::vector<IndicatorConstraint> out;
    for (const Entry& e : in_file_order(t)) {
      const std::string key = "study.constraints." + e.key;
      if (!find_indicator(e.key)) {
        fail(*e.node, key, "unknown indicator (indicators: " + join(indicator_names()) + ")");
      }
      const toml::table& c = table(*e.node, key, "must be { max = .. } and/or { min = .. }");
      IndicatorConstraint constraint{e.key, std::nullopt, std::nullopt};
      for (const Entry& f : in_file_order(c)) {
        if (f.key == "max") {
          constraint.max = number(*f.node, key + ".max");
        } else if (f.key == "min") {
          constraint.min = number(*f.node, key + ".min");
        } else {
          fail_unknown(*f.node, key + "." + f.key, "constraint keys", {"max", "min"});
        }
      }
      if (!constraint.min && !constraint.max) fail(*e.node, key, "needs max, min or both");
      if (constraint.min && constraint.max && !(*constraint.min <= *constraint.max)) {
        fail(*c.get("max"), key + ".max", "must be >= min");
      }
      out.push_back(constraint);
    }
    return out;
  }

  // [study.practical]: indicator = maximum, or indicator = { max = .., min = .. }. Every
  // indicator is >= 0 by definition, so a negative bound is a mistake, not a filter.
  std::vector<IndicatorConstraint> practical(const toml::node& node) const {
    const std::string key = "study.practical";
    const toml::table& t = table(node, key,
                                 "must be a table of indicator = maximum, e.g. "
                                 "{ eps_p = 0.03, nop_p = 15 }");
    const auto bound = [&](const toml::node& where, const std::string& where_key) {
      const double v = number(where, where_key);
      if (!(v >= 0.0)) fail(where, where_key, "must be >= 0 (indicators are never negative)");
      return v;
    };
    std::vector<IndicatorConstraint> out;
    for (const Entry& e : in_file_order(t)) {
      const std::string indicator_key = key + "." + e.key;
      if (!find_indicator(e.key)) {
        fail(*e.node, indicator_key,
             "unknown indicator (indicators: " + join(indicator_names()) + ")");
      }
      const auto& stored = plan_->output.indicators;
      if (!stored.empty() && std::find(stored.begin(), stored.end(), e.key) == stored.end()) {
        fail(*e.node, indicator_key,
             "is not among [output] indicators (" + join(stored) + "), so it is not stored");
      }
      IndicatorConstraint threshold{e.key, std::nullopt, std::nullopt};
      if (number_of(*e.node)) {
        threshold.max = bound(*e.node, indicator_key);
      } else if (const auto* limits = e.node->as_table()) {
        for (const Entry& f : in_file_order(*limits)) {
          if (f.key == "max") {
            threshold.max = bound(*f.node, indicator_key + ".max");
          } else if (f.key == "min") {
            threshold.min = bound(*f.node, indicator_key + ".min");
          } else {
            fail_unknown(*f.node, indicator_key + "." + f.key, "threshold keys", {"max", "min"});
          }
        }
        if (!threshold.min && !threshold.max) {
          fail(*e.node, indicator_key, "needs max, min or both");
        }
        if (threshold.min && threshold.max && !(*threshold.min <= *threshold.max)) {
          fail(*limits->get("max"), indicator_key + ".max", "must be >= min");
        }
      } else {
        fail(*e.node, indicator_key,
             "must be a number (the largest practical value) or { max = .., min = .. }");
      }
      out.push_back(threshold);
    }
    if (out.empty()) fail(node, key, "must name at least one indicator");
    return out;
  }

  // ---- kind = "spectral" ------------------------------------------------------------------

  void read_spectral(const toml::table& study) {
    SpectralStudy& out = plan_->spectral;
    const std::vector<std::string> known{"kind",  "omega_dt", "methods",
                                         "alpha", "delta",    "omega_dt_reference",
                                         "stability_omega_max"};
    const toml::node *omega_dt = nullptr, *methods = nullptr, *alpha = nullptr, *delta = nullptr;
    for (const Entry& e : in_file_order(study)) {
      const std::string key = "study." + e.key;
      const toml::node& node = *e.node;
      if (e.key == "kind") {
      } else if (e.key == "omega_dt") {
        omega_dt = &node;
        out.omega_dt = log_axis_values(node, key);
      } else if (e.key == "methods") {
        methods = &node;
        out.methods = spectral_methods(node, key);
      } else if (e.key == "alpha" || e.key == "delta") {
        (e.key == "alpha" ? alpha : delta) = &node;
        const toml::table& axis = table(
            node, key, "must be { from = .., to = .., partitions = .. } or { values = [..] }");
        std::vector<double> values = axis_values(axis, key);
        for (const double v : values) {
          // The same rule as the method's own (validate), so the map holds no invalid HHT.
          HhtParams hht{.alpha = e.key == "alpha" ? v : -0.5, .delta = 0.5};
          if (e.key == "delta") hht.delta = v;
          if (const auto error = validate(MethodParams{hht})) {
            fail(node, key,
                 "holds " + e.key + " = " + format_value(v) + ", which " + error->constraint);
          }
        }
        (e.key == "alpha" ? out.alpha : out.delta) = std::move(values);
      } else if (e.key == "omega_dt_reference" || e.key == "stability_omega_max") {
        const double v = number(node, key);
        if (!(v > 0.0)) fail(node, key, "must be > 0");
        (e.key == "omega_dt_reference" ? out.omega_dt_reference : out.stability_omega_max) = v;
      } else if (e.key == "practical") {
        fail(node, key, "is for grid and list studies (a spectral study has no indicators)");
      } else {
        fail_unknown(node, key, "spectral keys", known);
      }
    }
    if (!omega_dt) {
      fail_missing(study, "study.omega_dt",
                   "a spectral study needs omega_dt = { from = .., to = .., points = .. } "
                   "(log-spaced) or { values = [..] }");
    }
    if (!methods) {
      fail_missing(study, "study.methods",
                   "a spectral study needs methods = [{ method = \"..\", .. }, ..]");
    }
    const auto linear = [](double from, double to, int partitions) {
      std::vector<double> v(static_cast<std::size_t>(partitions) + 1);
      for (int i = 0; i < partitions; ++i) v[i] = from + i * (to - from) / partitions;
      v.back() = to;
      return v;
    };
    if (!alpha) out.alpha = linear(-0.5, 0.0, 20);
    if (!delta) out.delta = linear(0.0, 1.0, 40);
  }

  // { from, to, points }: `points` values spaced evenly in log(Ω), both ends included (the last
  // exactly `to`); or { values = [..] }. Every value > 0.
  std::vector<double> log_axis_values(const toml::node& node, const std::string& key) const {
    const toml::table& axis = table(
        node, key, "must be { from = .., to = .., points = .. } (log-spaced) or { values = [..] }");
    const toml::node *from = nullptr, *to = nullptr, *points = nullptr, *values = nullptr;
    for (const Entry& e : in_file_order(axis)) {
      if (e.key == "from") {
        from = e.node;
      } else if (e.key == "to") {
        to = e.node;
      } else if (e.key == "points") {
        points = e.node;
      } else if (e.key == "values") {
        values = e.node;
      } else {
        fail_unknown(*e.node, key + "." + e.key, "omega_dt keys",
                     {"from", "to", "points", "values"});
      }
    }
    if (values) {
      if (from || to || points) {
        fail(axis, key, "give either values or from, to and points, not both");
      }
      const auto* array = values->as_array();
      const std::string values_key = key + ".values";
      if (!array) fail(*values, values_key, "must be an array of numbers");
      if (array->empty()) fail(*values, values_key, "must hold at least one value");
      if (array->size() > static_cast<std::size_t>(kMaxGridPoints)) {
        fail(*values, values_key, "holds more than " + std::to_string(kMaxGridPoints) + " values");
      }
      std::vector<double> out;
      for (std::size_t k = 0; k < array->size(); ++k) {
        const std::string item_key = values_key + "[" + std::to_string(k) + "]";
        const double v = number(*array->get(k), item_key);
        if (!(v > 0.0)) fail(*array->get(k), item_key, "must be > 0");
        if (std::find(out.begin(), out.end(), v) != out.end()) {
          fail(*array->get(k), item_key, "repeats an earlier value");
        }
        out.push_back(v);
      }
      return out;
    }
    if (!from) fail_missing(axis, key + ".from", "omega_dt needs from, to and points, or values");
    if (!to) fail_missing(axis, key + ".to", "omega_dt needs from, to and points, or values");
    if (!points) {
      fail_missing(axis, key + ".points",
                   "omega_dt needs points (the number of log-spaced values), or values");
    }
    const double lo = number(*from, key + ".from");
    const double hi = number(*to, key + ".to");
    if (!(lo > 0.0)) fail(*from, key + ".from", "must be > 0 (the values are log-spaced)");
    if (!(hi > 0.0)) fail(*to, key + ".to", "must be > 0 (the values are log-spaced)");
    if (lo == hi) fail(*to, key + ".to", "equals from; use values = [..] for a single value");
    const std::int64_t n = integer(*points, key + ".points");
    if (n < 2) fail(*points, key + ".points", "must be >= 2 (both ends are included)");
    if (n > kMaxGridPoints) {
      fail(*points, key + ".points", "must be <= " + std::to_string(kMaxGridPoints));
    }
    std::vector<double> out(static_cast<std::size_t>(n));
    const double step = std::log(hi / lo) / static_cast<double>(n - 1);
    for (std::int64_t i = 0; i + 1 < n; ++i) {
      out[static_cast<std::size_t>(i)] = lo * std::exp(static_cast<double>(i) * step);
    }
    out.front() = lo;
    out.back() = hi;  // exactly as written
    return out;
  }

  // methods = [{ method = "newmark", delta = 0.3 }, ..]: each a method and its parameters, by
  // the names of [method] (with `method` for the name, as in list points), built by build().
  std::vector<SpectralMethod> spectral_methods(const toml::node& node,
                                               const std::string& key) const {
    const auto* array = node.as_array();
    if (!array) fail(node, key, "must be an array of tables { method = \"..\", .. }");
    if (array->empty()) fail(node, key, "must hold at least one method");
    std::vector<std::string> known;
    for (const ParameterInfo& info : parameter_table()) {
      if (info.group == ParameterGroup::method) known.push_back(info.name);
    }
    std::vector<SpectralMethod> out;
    for (std::size_t k = 0; k < array->size(); ++k) {
      const std::string item_key = key + "[" + std::to_string(k) + "]";
      const toml::table& item =
          table(*array->get(k), item_key, "must be a table { method = \"..\", .. }");
      SimulationSettings settings;
      std::string name, parameters;
      const toml::node* method_node = nullptr;
      for (const Entry& e : in_file_order(item)) {
        const std::string entry_key = item_key + "." + e.key;
        const ParameterInfo* info = find_parameter(e.key);
        if (!info || info->group != ParameterGroup::method) {
          fail_unknown(*e.node, entry_key, "method keys", known);
        }
        assign_at(settings, *info, *e.node, entry_key);
        const ParameterValue value = parameter_value(*e.node, *info, entry_key);
        const std::string text = std::holds_alternative<double>(value)
                                     ? format_value(std::get<double>(value))
                                     : std::get<std::string>(value);
        if (e.key == "method") {
          name = text;
          method_node = e.node;
        } else {
          parameters += " " + e.key + "=" + text;
        }
      }
      if (!method_node) {
        fail_missing(item, item_key + ".method",
                     "each method needs method = one of " + method_names());
      }
      auto built = build(settings);
      if (const auto* error = std::get_if<ParameterError>(&built)) {
        const toml::node* where = item.get(error->field);
        if (where) fail(*where, item_key + "." + error->field, error->constraint);
        fail_at(item, item_key + "." + error->field, error->value, error->constraint);
      }
      SpectralMethod method{std::get<Simulation>(built).method, name + parameters,
                            settings.method};
      for (std::size_t j = 0; j < out.size(); ++j) {
        if (out[j].label == method.label) {
          fail(*array->get(k), item_key,
               "repeats " + key + "[" + std::to_string(j) + "] (" + method.label + ")");
        }
      }
      out.push_back(std::move(method));
    }
    return out;
  }

  // A spectral study runs no simulation: [scene] and [method] would be ignored, so they are
  // errors; of [output] only `file` applies.
  void check_spectral_sections() const {
    for (const char* section : {"scene", "method"}) {
      if (const toml::node* node = root_->get(section)) {
        fail(*node, section,
             "a spectral study runs no simulation; give each method in study.methods");
      }
    }
    if (const toml::node* output = root_->get("output"); output && output->is_table()) {
      for (const Entry& e : in_file_order(*output->as_table())) {
        if (e.key != "file") {
          fail(*e.node, "output." + e.key, "is not used by a spectral study (only output.file is)");
        }
      }
    }
  }

  // ---- kind = "work-precision" ------------------------------------------------------------

  void read_work_precision(const toml::table& study) {
    WorkPrecisionStudy& out = plan_->work_precision;
    const std::vector<std::string> known{"kind", "methods", "elements", "courant", "repeats"};
    for (const Entry& e : in_file_order(study)) {
      const std::string key = "study." + e.key;
      const toml::node& node = *e.node;
      if (e.key == "kind") {
      } else if (e.key == "methods") {
        out.methods = spectral_methods(node, key);
        methods_node_ = &node;
      } else if (e.key == "elements") {
        elements_node_ = &node;
        for (const double v : number_list(node, key, "element counts")) {
          out.elements.push_back(static_cast<long>(v));
        }
      } else if (e.key == "courant") {
        courant_node_ = &node;
        out.courant = number_list(node, key, "Courant numbers");
      } else if (e.key == "repeats") {
        const std::int64_t n = integer(node, key);
        if (n < 1 || n > kMaxRepeats) {
          fail(node, key, "must be an integer from 1 to " + std::to_string(kMaxRepeats));
        }
        out.repeats = static_cast<int>(n);
      } else if (e.key == "practical" || e.key == "axes" || e.key == "points") {
        fail(node, key,
             "is not a key of a work-precision study (it varies elements and courant, for each "
             "of its methods)");
      } else {
        fail_unknown(node, key, "work-precision keys", known);
      }
    }
    if (out.methods.empty()) out.methods = default_work_precision_methods();
    if (plan_->base.model) {
      // A model's mesh is fixed: its one "element count" is its DOF count.
      if (elements_node_) {
        fail(*elements_node_, "study.elements",
             "does not apply to a model (kind = \"matrices\"): its mesh is the user's; vary "
             "courant");
      }
      out.elements = {static_cast<long>(plan_->base.model->model->size())};
    }
    if (out.elements.empty()) out.elements = {50, 100, 200, 400, 800};
    if (out.courant.empty()) out.courant = {0.25, 0.5, 1.0, 2.0, 4.0};
    const long points = static_cast<long>(out.methods.size() * out.elements.size() *
                                          out.courant.size());
    if (points > kMaxGridPoints) {
      fail(study, "study", "has " + std::to_string(points) + " points, more than " +
                               std::to_string(kMaxGridPoints));
    }
  }

  // elements = [50, 100] or courant = [0.5, 1.0]: a non-empty array of numbers, each > 0 and
  // finite, no value twice; element counts must be integers.
  std::vector<double> number_list(const toml::node& node, const std::string& key,
                                  const char* what) const {
    const bool integers = std::string_view(what) == "element counts";
    const auto* array = node.as_array();
    if (!array) {
      fail(node, key, std::string("must be an array of ") + what +
                          (integers ? ", e.g. [50, 100, 200]" : ", e.g. [0.5, 1.0, 2.0]"));
    }
    if (array->empty()) fail(node, key, "must hold at least one value");
    if (array->size() > static_cast<std::size_t>(kMaxGridPoints)) {
      fail(node, key, "holds more than " + std::to_string(kMaxGridPoints) + " values");
    }
    std::vector<double> out;
    for (std::size_t k = 0; k < array->size(); ++k) {
      const toml::node& item = *array->get(k);
      const std::string item_key = key + "[" + std::to_string(k) + "]";
      const double v = integers ? static_cast<double>(integer(item, item_key))
                                : number(item, item_key);
      if (!(v > 0.0)) fail(item, item_key, integers ? "must be >= 1" : "must be > 0");
      if (std::find(out.begin(), out.end(), v) != out.end()) {
        fail(item, item_key, "repeats an earlier value");
      }
      out.push_back(v);
    }
    return out;
  }

  // The methods this project recommends (README.md, "Decisions and findings"; the spectral
  // plan's set): what a work-precision study compares unless the plan lists its own.
  static std::vector<SpectralMethod> default_work_precision_methods() {
    const auto make = [](MethodKind kind, std::vector<std::pair<const char*, double>> given,
                         std::string label) {
      SimulationSettings simulation;
      simulation.method.kind = kind;
      for (const auto& [name, value] : given) simulation.method.given.set(name, value);
      return SpectralMethod{std::get<Simulation>(build(simulation)).method, std::move(label),
                            simulation.method};
    };
    return {
        make(MethodKind::central_difference, {}, "cdm"),
        make(MethodKind::backward_euler, {}, "backward-euler"),
        make(MethodKind::newmark, {{"delta", 0.3}}, "newmark delta=0.3"),
        make(MethodKind::hht, {{"delta", 0.45}, {"alpha", -0.3}}, "hht alpha=-0.3 delta=0.45"),
        make(MethodKind::generalized_alpha, {{"rho_inf", 0.8}}, "generalized-alpha rho_inf=0.8")};
  }

  // The study sets the method, the mesh and the step: [method] would be ignored, and so would
  // [scene] elements, courant and dt; [output] indicators and histories do not apply (the
  // columns are fixed, no histories are kept).
  void check_work_precision_sections() const {
    if (const toml::node* node = root_->get("method")) {
      fail(*node, "method", "a work-precision study gives each method in study.methods");
    }
    if (const toml::node* scene = root_->get("scene"); scene && scene->is_table()) {
      for (const char* key : {"elements", "courant", "dt"}) {
        if (const toml::node* node = scene->as_table()->get(key)) {
          fail(*node, "scene."s + key,
               std::string("is set by the work-precision study: give ") +
                   (std::string_view(key) == "elements" ? "study.elements" : "study.courant") +
                   " instead");
        }
      }
    }
    if (const toml::node* output = root_->get("output"); output && output->is_table()) {
      for (const char* key : {"indicators", "histories"}) {
        if (const toml::node* node = output->as_table()->get(key)) {
          fail(*node, "output."s + key,
               "is not used by a work-precision study (its columns are fixed: results/README.md)");
        }
      }
    }
  }

  // Every point built on [scene] (a scene may be valid at one mesh and not another: t_end
  // shorter than a step, say); an error names the first bad point.
  void check_work_precision() const {
    const WorkPrecisionStudy& wp = plan_->work_precision;
    for (std::size_t m = 0; m < wp.methods.size(); ++m) {
      for (const long n : wp.elements) {
        for (const double c : wp.courant) {
          SimulationSettings settings;
          std::optional<ParameterError> error = assign_work_precision_point(
              *plan_, static_cast<long>(m), n, c, settings);
          if (!error) {
            auto built = build(settings);
            if (auto* e = std::get_if<ParameterError>(&built)) error = *e;
          }
          if (!error) continue;
          const std::string suffix = " (at method " + wp.methods[m].label + ", elements " +
                                     std::to_string(n) + ", courant " + format_value(c) + ")";
          if (error->field == "elements" && elements_node_) {
            fail_at(*elements_node_, "study.elements", error->value, error->constraint + suffix);
          }
          if (error->field == "courant" && courant_node_) {
            fail_at(*courant_node_, "study.courant", error->value, error->constraint + suffix);
          }
          const ParameterInfo* info = find_parameter(error->field);
          if (info && info->group == ParameterGroup::method && methods_node_) {
            fail_at(*methods_node_, "study.methods", error->value, error->constraint + suffix);
          }
          fail_base(*error, suffix);
        }
      }
    }
  }

  // ---- checks across parameters -----------------------------------------------------------

  // Where a build() error about `field` is reported when the study does not vary it: its key
  // in [scene], [method] or [output] if written there, else the section (or the file start).
  [[noreturn]] void fail_base(const ParameterError& error, const std::string& suffix) const {
    if (is_scene_path(error.field) || error.field.starts_with("body")) {  // the bodies' keys
      const toml::node* section = root_->get("scene");
      fail_at(section ? *section : static_cast<const toml::node&>(*root_), "scene." + error.field,
              error.value, error.constraint + suffix);
    }
    const ParameterInfo* info = find_parameter(error.field);
    if (info) {
      if (const toml::node* node = base_node(*info)) {
        fail(*node, base_key(*info), error.constraint + suffix);
      }
      const toml::node* section = root_->get(section_of(info->group));
      fail_at(section ? *section : static_cast<const toml::node&>(*root_), base_key(*info),
              error.value, error.constraint + suffix);
    }
    fail_at(*root_, error.field, error.value, error.constraint + suffix);
  }

  std::set<std::string> varied_names() const {
    std::set<std::string> out;
    for (const GridAxis& axis : plan_->axes) out.insert(axis.name);
    for (const CoupledAxis& axis : plan_->coupled) out.insert(axis.name);
    for (const ListPoint& point : plan_->points) {
      for (const auto& entry : point) out.insert(entry.first);
    }
    for (const OptimizeParameter& p : plan_->optimize.parameters) out.insert(p.name);
    return out;
  }

  // The base on its own, so that a wrong fixed value is reported at its key once rather than
  // at the first point. Errors about a parameter the study varies (or with the method varied
  // by a list) are left to the points, where the varied values are known.
  void check_base() const {
    // A work-precision study sets the mesh and the step of every point: its points are built,
    // and reported, by check_work_precision().
    if (plan_->kind == StudyKind::work_precision) return;
    const auto built = build(plan_->base);
    const auto* error = std::get_if<ParameterError>(&built);
    if (!error) return;
    const std::set<std::string> varied = varied_names();
    if (varied.count(error->field) || varied.count("method")) return;
    fail_base(*error, "");
  }

  void check_points() const {
    if (plan_->kind == StudyKind::optimize) {
      check_optimize();
      return;
    }
    if (plan_->kind == StudyKind::spectral) return;  // its methods were built as they were read
    if (plan_->kind == StudyKind::work_precision) {
      check_work_precision();
      return;
    }
    const PointSet points(*plan_);
    for (long k = 0; k < points.size(); ++k) {
      SimulationSettings settings = plan_->base;
      std::optional<ParameterError> error = points.apply(k, settings);
      if (!error) {
        auto built = build(settings);
        if (auto* e = std::get_if<ParameterError>(&built)) error = *e;
      }
      if (!error) continue;
      if (plan_->kind == StudyKind::grid) {
        const std::string suffix =
            " (at grid point " + std::to_string(k) + ": " +
            values_text(points.parameter_names(), points.parameter_values(k)) + ")";
        const auto axis = axis_nodes_.find(error->field);
        if (axis != axis_nodes_.end()) {
          fail_at(*axis->second, "study.axes." + error->field, error->value,
                  error->constraint + suffix);
        }
        fail_base(*error, suffix);
      }
      const std::string point_key = "study.points[" + std::to_string(k) + "]";
      const std::string suffix = " (at list point " + std::to_string(k) + ")";
      const toml::table& point = *points_->get(static_cast<std::size_t>(k))->as_table();
      if (const toml::node* node = point.get(error->field)) {
        fail(*node, point_key + "." + error->field, error->constraint + suffix);
      }
      const ParameterInfo* info = find_parameter(error->field);
      if (info && base_node(*info)) fail_base(*error, suffix);
      fail_at(point, point_key + "." + error->field, error->value, error->constraint + suffix);
    }
  }

  // Every optimisation parameter is built at the start point and at each of its bounds (the
  // others at their start): the settings' rules are per parameter, so a box that passes these
  // holds no point that build() rejects.
  void check_optimize() const {
    const auto& parameters = plan_->optimize.parameters;
    std::vector<double> start;
    for (const OptimizeParameter& p : parameters) {
      start.push_back(p.initial());
    }
    enum class Where { start, lower, upper };
    const auto check = [&](std::size_t moved, Where where) {
      std::vector<double> x = start;
      if (where == Where::lower) x[moved] = parameters[moved].lower;
      if (where == Where::upper) x[moved] = parameters[moved].upper;
      std::vector<std::string> names;
      for (const OptimizeParameter& p : parameters) names.push_back(p.name);
      const std::string suffix = where == Where::start
                                     ? " (at the start point: " + values_text(names, x) + ")"
                                     : " (with " + parameters[moved].name + " at its " +
                                           (where == Where::lower ? "lower" : "upper") +
                                           " bound: " + values_text(names, x) + ")";

      SimulationSettings settings = plan_->base;
      std::optional<ParameterError> error;
      for (std::size_t k = 0; k < parameters.size() && !error; ++k) {
        error = assign(settings, parameters[k].name, x[k]);
      }
      if (!error) {
        auto built = build(settings);
        if (auto* e = std::get_if<ParameterError>(&built)) error = *e;
      }
      if (!error) return;
      const auto found = parameter_nodes_.find(error->field);
      if (found == parameter_nodes_.end()) fail_base(*error, suffix);
      const ParameterNodes& nodes = found->second;
      const std::string key = "study.parameters." + error->field;
      const bool is_moved = error->field == parameters[moved].name;
      if (is_moved && where == Where::lower) {
        fail(*nodes.from, key + ".from", error->constraint + suffix);
      }
      if (is_moved && where == Where::upper) {
        fail(*nodes.to, key + ".to", error->constraint + suffix);
      }
      if (nodes.start) fail(*nodes.start, key + ".start", error->constraint + suffix);
      fail(*nodes.table, key, error->constraint + suffix);
    };
    check(0, Where::start);
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      check(k, Where::lower);
      check(k, Where::upper);
    }
  }

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

}  // namespace

const char* to_string(StudyKind kind) {
  switch (kind) {
    case StudyKind::grid:
      return "grid";
    case StudyKind::list:
      return "list";
    case StudyKind::optimize:
      return "optimize";
    case StudyKind::spectral:
      return "spectral";
    case StudyKind::work_precision:
      return "work-precision";
  }
  return "unknown";
}

namespace {

// The TOML of `text`, read from `file`; a syntax error throws PlanError "file:line:column: what".
toml::table parse_toml(const std::string& text, const std::string& file) {
  try {
    return toml::parse(std::string_view(text), std::string_view(file));
  } catch (const toml::parse_error& e) {
    const toml::source_position p = e.source().begin;
    throw PlanError(file + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": " +
                    std::string(e.description()));
  }
}

// The whole of a file, or PlanError naming it and what it is (`what`: "plan", "scene").
std::string read_text(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PlanError(path.string() + ": cannot open the " + what + " file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw PlanError(path.string() + ": cannot read the " + what + " file");
  return text.str();
}

}  // namespace

Plan parse_plan(const std::string& text, const std::filesystem::path& source) {
  const std::string file = source.string();
  const toml::table root = parse_toml(text, file);
  Plan plan;
  plan.path = source;
  plan.name = source.stem().empty() ? "plan" : source.stem().string();
  plan.text = text;
  PlanReader(plan.text, file).read(root, plan);
  return plan;
}

SimulationSettings load_scene_file(const std::filesystem::path& path) {
  return parse_scene_file(read_text(path, "scene"), path);
}

SimulationSettings parse_scene_file(const std::string& text, const std::filesystem::path& source) {
  return PlanReader(text, source.string()).read_scene_file(parse_toml(text, source.string()));
}

Plan load_plan(const std::filesystem::path& path) {
  return parse_plan(read_text(path, "plan"), path);
}

}  // namespace impactid
