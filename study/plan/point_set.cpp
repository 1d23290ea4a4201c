#include "study/plan/point_set.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <variant>

#include "study/plan/scene_path.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_numeric(const std::string& name) {
  if (is_scene_path(name)) return name != "primary_contact";  // a scene of bodies' numbers
  const ParameterInfo* info = find_parameter(name);
  return info && info->kind != ParameterKind::choice;
}

}  // namespace

PointSet::PointSet(const Plan& plan) : plan_(&plan) {
  assert(plan.kind == StudyKind::grid || plan.kind == StudyKind::list);
  if (plan.kind == StudyKind::grid) {
    size_ = plan.axes.empty() ? 0 : 1;
    for (const GridAxis& axis : plan.axes) {
      dimension_names_.push_back(axis.name);
      dimension_values_.push_back(axis.values);
      dimension_labels_.push_back(axis.labels);
      parameter_names_.push_back(axis.name);
      size_ *= static_cast<long>(axis.values.size());
    }
    for (const CoupledAxis& coupled : plan.coupled) parameter_names_.push_back(coupled.name);
    return;
  }

  size_ = static_cast<long>(plan.points.size());
  dimension_names_.push_back("point");
  dimension_values_.emplace_back();
  dimension_labels_.emplace_back();
  for (long k = 0; k < size_; ++k) dimension_values_[0].push_back(static_cast<double>(k));
  for (const ListPoint& point : plan.points) {
    for (const auto& [name, value] : point) {
      if (is_numeric(name) && std::holds_alternative<double>(value) &&
          std::find(parameter_names_.begin(), parameter_names_.end(), name) ==
              parameter_names_.end()) {
        parameter_names_.push_back(name);
      }
    }
  }
  // A list is short, and what a point leaves out is only known once it is built.
  for (long k = 0; k < size_; ++k) {
    SimulationSettings s = plan.base;
    std::optional<Simulation> simulation;
    if (!apply(k, s)) {
      if (auto built = build(s); auto* sim = std::get_if<Simulation>(&built)) simulation = *sim;
    }
    const ListPoint& point = plan.points[static_cast<std::size_t>(k)];
    std::vector<double> values;
    for (const std::string& name : parameter_names_) {
      const auto given = std::find_if(point.begin(), point.end(),
                                      [&](const auto& entry) { return entry.first == name; });
      if (given != point.end() && std::holds_alternative<double>(given->second)) {
        values.push_back(std::get<double>(given->second));
      } else if (simulation) {
        values.push_back(numeric_value(*simulation, name).value_or(kNaN));
      } else {
        values.push_back(kNaN);
      }
    }
    list_values_.push_back(std::move(values));
  }
}

std::vector<long> PointSet::shape() const {
  std::vector<long> out;
  for (const auto& values : dimension_values_) out.push_back(static_cast<long>(values.size()));
  return out;
}

std::vector<long> PointSet::grid_indices(long index) const {
  assert(plan_->kind == StudyKind::grid && index >= 0 && index < size_);
  std::vector<long> out(dimension_values_.size());
  for (std::size_t d = dimension_values_.size(); d-- > 0;) {
    const auto n = static_cast<long>(dimension_values_[d].size());
    out[d] = index % n;
    index /= n;
  }
  return out;
}

std::vector<double> PointSet::parameter_values(long index) const {
  assert(index >= 0 && index < size_);
  if (plan_->kind == StudyKind::list) return list_values_[static_cast<std::size_t>(index)];

  const std::vector<long> at = grid_indices(index);
  std::vector<double> independent;
  for (std::size_t d = 0; d < at.size(); ++d) {
    independent.push_back(dimension_values_[d][static_cast<std::size_t>(at[d])]);
  }
  const auto lookup = [&](const std::string& name) {
    const auto it = std::find(dimension_names_.begin(), dimension_names_.end(), name);
    // load_plan() lets a coupled axis use independent axes only.
    assert(it != dimension_names_.end());
    return independent[static_cast<std::size_t>(it - dimension_names_.begin())];
  };
  std::vector<double> values = independent;
  for (const CoupledAxis& coupled : plan_->coupled) {
    values.push_back(coupled.expression.evaluate(lookup));
  }
  return values;
}

std::optional<ParameterError> PointSet::apply(long index, SimulationSettings& settings) const {
  assert(index >= 0 && index < size_);
  if (plan_->kind == StudyKind::list) {
    for (const auto& [name, value] : plan_->points[static_cast<std::size_t>(index)]) {
      if (auto error = impactid::assign(settings, name, value)) return error;
    }
    return std::nullopt;
  }
  const std::vector<double> values = parameter_values(index);
  for (std::size_t k = 0; k < values.size(); ++k) {
    // The first parameters are the axes, in dimension order; a choice axis applies its word.
    const std::vector<std::string>* labels =
        k < dimension_labels_.size() && !dimension_labels_[k].empty() ? &dimension_labels_[k]
                                                                      : nullptr;
    const ParameterValue value =
        labels ? ParameterValue((*labels)[static_cast<std::size_t>(values[k])])
               : ParameterValue(values[k]);
    if (auto error = impactid::assign(settings, parameter_names_[k], value)) return error;
  }
  return std::nullopt;
}

SimulationSettings PointSet::settings(long index) const {
  SimulationSettings s = plan_->base;
  [[maybe_unused]] const auto error = apply(index, s);
  assert(!error && "PointSet::settings() on a point load_plan() did not check");
  return s;
}

}  // namespace impactid
