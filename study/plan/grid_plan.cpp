#include "study/plan/plan_reader.hpp"

namespace impactid::plan_reading {

void PlanReader::read_grid(const toml::table& study) {
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
    const ParameterInfo& info = varied_parameter(e, key, "a grid axis", true);
    axis_nodes_[e.key] = e.node;
    if (std::string_view(info.name) == "method") {
      // Each method takes its own parameters, and a results file names one method.
      fail(*e.node, key, "is not an axis: compare methods in a list or a work-precision study");
    }
    if (info.kind == ParameterKind::choice) {
      const auto* t = e.node->as_table();
      if (!t) fail(*e.node, key, "a choice axis is { values = [\"word\", ..] }");
      GridAxis axis{e.key, {}, choice_axis_labels(*t, key, info)};
      for (std::size_t k = 0; k < axis.labels.size(); ++k) {
        axis.values.push_back(static_cast<double>(k));
      }
      plan_->axes.push_back(std::move(axis));
    } else if (e.node->is_string()) {
      coupled.push_back(&e);
    } else if (const auto* t = e.node->as_table()) {
      plan_->axes.push_back({e.key, axis_values(*t, key), {}});
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
           "the grid has more than " + std::to_string(kMaxGridPoints) + " points; split the study");
    }
  }

  std::vector<std::string> independent;
  for (const GridAxis& axis : plan_->axes) {
    if (axis.labels.empty()) independent.push_back(axis.name);
  }
  for (const Entry* e : coupled) {
    const std::string key = "study.axes." + e->key;
    std::string error;
    auto expression = AxisExpression::parse(e->node->as_string()->get(), error);
    if (!expression) fail(*e->node, key, "invalid expression: " + error);
    for (const std::string& name : expression->variables()) {
      if (std::find(independent.begin(), independent.end(), name) != independent.end()) continue;
      const bool is_choice = std::any_of(plan_->axes.begin(), plan_->axes.end(),
                                         [&](const GridAxis& axis) { return axis.name == name; });
      if (is_choice) {
        fail(*e->node, key,
             "uses '" + name + "', a choice axis: an expression may use only numeric axes (" +
                 join(independent) + ")");
      }
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

std::vector<double> PlanReader::listed_values(const toml::node& values,
                                              const std::string& values_key, bool positive) const {
  const auto* array = values.as_array();
  if (!array) fail(values, values_key, "must be an array of numbers");
  if (array->empty()) fail(values, values_key, "must hold at least one value");
  if (array->size() > static_cast<std::size_t>(kMaxGridPoints)) {
    fail(values, values_key, "holds more than " + std::to_string(kMaxGridPoints) + " values");
  }
  std::vector<double> out;
  for (std::size_t k = 0; k < array->size(); ++k) {
    const std::string item_key = values_key + "[" + std::to_string(k) + "]";
    const double v = number(*array->get(k), item_key);
    if (positive && !(v > 0.0)) fail(*array->get(k), item_key, "must be > 0");
    if (std::find(out.begin(), out.end(), v) != out.end()) {
      fail(*array->get(k), item_key, "repeats an earlier value");
    }
    out.push_back(v);
  }
  return out;
}

std::vector<double> PlanReader::axis_values(const toml::table& axis, const std::string& key) const {
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
      fail_unknown(*e.node, key + "." + e.key, "axis keys", {"from", "to", "partitions", "values"});
    }
  }
  if (values) {
    if (from || to || partitions) {
      fail(axis, key, "give either values or from, to and partitions, not both");
    }
    return listed_values(*values, key + ".values");
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

std::vector<std::string> PlanReader::choice_axis_labels(const toml::table& axis,
                                                        const std::string& key,
                                                        const ParameterInfo& info) const {
  const toml::node* values = nullptr;
  for (const Entry& e : in_file_order(axis)) {
    if (e.key != "values") {
      fail_unknown(*e.node, key + "." + e.key, "a choice axis has only", {"values"});
    }
    values = e.node;
  }
  if (!values) fail_missing(axis, key + ".values", "a choice axis lists its words in values");
  const std::string values_key = key + ".values";
  const auto* array = values->as_array();
  if (!array) fail(*values, values_key, "must be an array of words ("s + info.choices + ")");
  if (array->empty()) fail(*values, values_key, "must hold at least one word");
  std::vector<std::string> out;
  for (std::size_t k = 0; k < array->size(); ++k) {
    const toml::node& item = *array->get(k);
    const std::string item_key = values_key + "[" + std::to_string(k) + "]";
    if (!item.is_string()) fail(item, item_key, "must be a word ("s + info.choices + ")");
    const std::string word = item.as_string()->get();
    SimulationSettings check = plan_->base;
    if (const auto error = assign(check, info.name, ParameterValue(word))) {
      fail(item, item_key, error->constraint);
    }
    if (std::find(out.begin(), out.end(), word) != out.end()) {
      fail(item, item_key, "repeats an earlier word");
    }
    out.push_back(word);
  }
  return out;
}

void PlanReader::read_list(const toml::table& study) {
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

void PlanReader::check_points() const {
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
      const std::string suffix = " (at grid point " + std::to_string(k) + ": " +
                                 values_text(points.parameter_names(), points.parameter_values(k)) +
                                 ")";
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

}  // namespace impactid::plan_reading
