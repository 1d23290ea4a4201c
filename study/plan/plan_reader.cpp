// PlanReader, and the plan and scene loading of study/plan/plan.hpp that it does.
#include "study/plan/plan_reader.hpp"

#include <fstream>
#include <utility>
#include <vector>

#include "study/plan/plan.hpp"

namespace impactid::plan_reading {

SimulationSettings PlanReader::read_scene_file(const toml::table& root) {
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

void PlanReader::read(const toml::table& root, Plan& plan) {
  root_ = &root;
  plan_ = &plan;
  read_root();
  check_base();
  check_points();
  if (plan.output.file.empty()) plan.output.file = "results/" + plan.name + ".h5";
  if (plan.output.indicators.empty()) plan.output.indicators = indicator_names();
}

[[noreturn]] void PlanReader::fail_at(const toml::node& where, const std::string& key,
                                      const std::string& value, const std::string& what) const {
  const toml::source_position p = where.source().begin;
  throw PlanError(file_ + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": " +
                  key + " = " + value + ": " + what);
}

[[noreturn]] void PlanReader::fail(const toml::node& node, const std::string& key,
                                   const std::string& what) const {
  fail_at(node, key, written(node), what);
}

[[noreturn]] void PlanReader::fail_missing(const toml::node& table, const std::string& key,
                                           const std::string& what) const {
  fail_at(table, key, "(missing)", what);
}

[[noreturn]] void PlanReader::fail_unknown(const toml::node& node, const std::string& key,
                                           const std::string& context,
                                           const std::vector<std::string>& known) const {
  fail(node, key, "unknown key (" + context + ": " + join(known) + ")");
}

std::size_t PlanReader::offset(toml::source_position p) const {
  if (p.line == 0 || p.line > line_starts_.size() || p.column == 0) return std::string::npos;
  std::size_t i = line_starts_[p.line - 1];
  for (toml::source_index c = 1; c < p.column; ++c) {
    if (i >= text_.size() || text_[i] == '\n') return std::string::npos;
    ++i;
    while (i < text_.size() && (static_cast<unsigned char>(text_[i]) & 0xC0) == 0x80) ++i;
  }
  return i;
}

std::string PlanReader::written(const toml::node& node) const {
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

std::string PlanReader::rendered(const toml::node& node) const {
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

const toml::table& PlanReader::table(const toml::node& node, const std::string& key,
                                     const std::string& what) const {
  if (const auto* t = node.as_table()) return *t;
  fail(node, key, what);
}

std::string PlanReader::string(const toml::node& node, const std::string& key) const {
  if (const auto* s = node.as_string()) return s->get();
  fail(node, key, "must be a string");
}

double PlanReader::number(const toml::node& node, const std::string& key) const {
  const auto v = number_of(node);
  if (!v) fail(node, key, "must be a number");
  if (!std::isfinite(*v)) fail(node, key, "must be finite");
  return *v;
}

ParameterValue PlanReader::parameter_value(const toml::node& node, const ParameterInfo& info,
                                           const std::string& key) const {
  if (const auto v = number_of(node)) return *v;
  if (const auto* s = node.as_string()) return s->get();
  if (info.kind == ParameterKind::choice) {
    fail(node, key, "must be a string, one of "s + info.choices);
  }
  fail(node, key, info.kind == ParameterKind::integer ? "must be an integer" : "must be a number");
}

void PlanReader::assign_at(SimulationSettings& settings, const ParameterInfo& info,
                           const toml::node& node, const std::string& key) const {
  if (auto error = assign(settings, info.name, parameter_value(node, info, key))) {
    fail(node, key, error->constraint);
  }
}

void PlanReader::read_root() {
  const std::vector<std::string> known{"name", "description", "scene", "method", "study", "output"};
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
      if (const toml::node* file = scene.get("scene"); file && file->is_string()) {
        // TOML puts a key under the last [table] header above it: `scene = "FILE"` written after
        // [scene] is scene.scene, which is no key of a scene.
        fail(*file, "scene.scene",
             "a scene file is named by the top-level key scene = " + written(*file) +
                 ", on a line above the plan's first [table] header, not under [scene]: move it "
                 "there and remove [scene] (a plan's scene is either a [scene] table or a scene "
                 "file; docs/model-files.md)");
      }
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

void PlanReader::read_model(const toml::table& scene) {
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
    plan_->base.model = read_model_scene(scene, "scene", std::filesystem::path(file_).parent_path(),
                                         [this](const toml::node& at, const std::string& key,
                                                const std::string& what) { fail(at, key, what); });
  }
}

void PlanReader::read_parameters(const toml::table& section, ParameterGroup group,
                                 const char* name) {
  for (const Entry& e : in_file_order(section)) {
    const std::string key = name + "."s + e.key;
    if (group == ParameterGroup::scene && plan_->base.bodies && is_scene_of_bodies_key(e.key)) {
      continue;  // read by read_scene_of_bodies
    }
    if (group == ParameterGroup::scene && plan_->base.model && is_model_scene_key(e.key)) {
      continue;  // read by read_model_scene
    }
    if (group == ParameterGroup::scene && is_scene_of_bodies_key(e.key)) {
      fail(*e.node, key,
           plan_->base.model
               ? "is a key of scenes of bodies ([[scene.body]]), not of a model of matrices (a "
                 "model's load is its [scene.load] table)"
               : "is a key of scenes of bodies ([[scene.body]]); this scene is the one-body rod "
                 "(length, elements, velocity, gap, ...): write it as a body to give it");
    }
    const ParameterInfo* info = find_parameter(e.key);
    if (!info || info->group != group) {
      fail_unknown(*e.node, key, name + " keys"s, parameter_names(group));
    }
    assign_at(plan_->base, *info, *e.node, key);
  }
}

void PlanReader::read_method(const toml::table& section) {
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

void PlanReader::read_output(const toml::table& section) {
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

void PlanReader::read_study(const toml::table& study) {
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

const toml::node* PlanReader::base_node(const ParameterInfo& info) const {
  const toml::node* section = root_->get(section_of(info.group));
  if (!section || !section->is_table()) return nullptr;
  return section->as_table()->get(std::string_view(info.name) == "method" ? "name" : info.name);
}

const ParameterInfo& PlanReader::varied_parameter(const Entry& e, const std::string& key,
                                                  const char* what, bool choices) const {
  if (is_scene_path(e.key)) return varied_scene_path(e, key, what);
  const ParameterInfo* info = find_parameter(e.key);
  if (!info) {
    fail(*e.node, key,
         "is not a parameter (numeric parameters: " + join(numeric_parameter_names()) + ")");
  }
  if (info->kind == ParameterKind::choice && !choices) {
    fail(*e.node, key,
         "is a choice parameter ("s + info->choices + "): only numeric parameters can be " + what +
             "; vary choices as a grid axis or in a list study");
  }
  if (base_node(*info)) {
    fail(*e.node, key,
         "is also set as " + base_key(*info) + ": a parameter is either fixed or " + what);
  }
  return *info;
}

const ParameterInfo& PlanReader::varied_scene_path(const Entry& e, const std::string& key,
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

std::vector<IndicatorConstraint> PlanReader::constraints(const toml::table& t) const {
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

std::vector<IndicatorConstraint> PlanReader::practical(const toml::node& node) const {
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

std::vector<SpectralMethod> PlanReader::spectral_methods(const toml::node& node,
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
    SpectralMethod method{std::get<Simulation>(built).method, name + parameters, settings.method};
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

std::vector<double> PlanReader::number_list(const toml::node& node, const std::string& key,
                                            const char* what) const {
  const bool integers = std::string_view(what) == "element counts";
  const auto* array = node.as_array();
  if (!array) {
    fail(node, key,
         std::string("must be an array of ") + what +
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
    const double v =
        integers ? static_cast<double>(integer(item, item_key)) : number(item, item_key);
    if (!(v > 0.0)) fail(item, item_key, integers ? "must be >= 1" : "must be > 0");
    if (std::find(out.begin(), out.end(), v) != out.end()) {
      fail(item, item_key, "repeats an earlier value");
    }
    out.push_back(v);
  }
  return out;
}

[[noreturn]] void PlanReader::fail_base(const ParameterError& error,
                                        const std::string& suffix) const {
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

std::set<std::string> PlanReader::varied_names() const {
  std::set<std::string> out;
  for (const GridAxis& axis : plan_->axes) out.insert(axis.name);
  for (const CoupledAxis& axis : plan_->coupled) out.insert(axis.name);
  for (const ListPoint& point : plan_->points) {
    for (const auto& entry : point) out.insert(entry.first);
  }
  for (const OptimizeParameter& p : plan_->optimize.parameters) out.insert(p.name);
  return out;
}

void PlanReader::check_base() const {
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

}  // namespace impactid::plan_reading

namespace impactid {

using plan_reading::PlanReader;

namespace {

// toml++ reads a table header nested to any depth ([a.a.a…] 30,000 times is a 60 KB file), and
// the readers and their messages walk tables recursively, so such a file would overflow the
// stack. No plan, scene or model file needs more than a few levels.
constexpr int kMaxNesting = 32;

// The first node nested deeper than kMaxNesting tables and arrays, or nullptr. An explicit
// stack, so that the check itself does not recurse.
const toml::node* nested_too_deep(const toml::table& root) {
  std::vector<std::pair<const toml::node*, int>> pending{{&root, 0}};
  while (!pending.empty()) {
    const auto [node, depth] = pending.back();
    pending.pop_back();
    if (depth > kMaxNesting) return node;
    if (const auto* t = node->as_table()) {
      for (const auto& [key, value] : *t) pending.emplace_back(&value, depth + 1);
    } else if (const auto* a = node->as_array()) {
      for (const toml::node& value : *a) pending.emplace_back(&value, depth + 1);
    }
  }
  return nullptr;
}

// The TOML of `text`, read from `file`; a syntax error, or tables nested too deep, throws
// PlanError "file:line:column: what".
toml::table parse_toml(const std::string& text, const std::string& file) {
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(file));
  } catch (const toml::parse_error& e) {
    const toml::source_position p = e.source().begin;
    throw PlanError(file + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": " +
                    std::string(e.description()));
  }
  if (const toml::node* deep = nested_too_deep(root)) {
    const toml::source_position p = deep->source().begin;
    throw PlanError(file + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) +
                    ": tables and arrays nested more than " + std::to_string(kMaxNesting) +
                    " levels deep (a plan, scene or model file needs a few)");
  }
  return root;
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
