// The points of a grid or list plan, each identified by its flat index: row-major over the
// grid axes in file order (the last axis varies fastest), or the position in a list. The
// index is all a worker needs to rebuild a point, so a set of indices can be handed to
// another thread, process or cluster job.
//
// Thread safety: a PointSet is immutable after construction, so every const member may be
// called from any number of threads at once. It refers to the Plan it was made from, which must
// outlive it and stay unchanged.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

class PointSet {
 public:
  explicit PointSet(const Plan& plan);  ///< grid or list plans

  long size() const { return size_; }
  /// Grid: one dimension per independent axis. List: one dimension "point" = 0..K−1.
  const std::vector<std::string>& dimension_names() const { return dimension_names_; }
  const std::vector<std::vector<double>>& dimension_values() const { return dimension_values_; }
  /// A choice axis's words (its values are their positions); empty for any other dimension.
  const std::vector<std::vector<std::string>>& dimension_labels() const {
    return dimension_labels_;
  }
  std::vector<long> shape() const;

  /// Parameters that vary between points, numeric ones: grid: the independent axes (a choice
  /// axis by the position of its word) then the coupled axes, in file order; list: every numeric
  /// key of any point, in order of first appearance (choice keys such as `mass` or `method` are
  /// applied but not listed).
  const std::vector<std::string>& parameter_names() const { return parameter_names_; }
  /// Their values at a point, in parameter_names() order. Grid: the axis values and the coupled
  /// values computed from them. List: the value the point gives; for a key the point leaves out,
  /// the value in effect there (numeric_value() of the built point: the base value or the
  /// method's default), NaN if the point's method has no such parameter.
  std::vector<double> parameter_values(long index) const;

  /// Base settings with the point's values applied. Points were checked by load_plan(), so
  /// this does not fail for a loaded plan.
  SimulationSettings settings(long index) const;
  /// The same, for checking a plan: applies the point's values to `settings` (normally a copy
  /// of the base) — grid: in parameter_names() order; list: the point's keys in file order —
  /// and returns the first error assign() reports. Range and cross-parameter rules are left to
  /// build().
  std::optional<ParameterError> apply(long index, SimulationSettings& settings) const;

  /// Grid: the index of each axis at a flat index (row-major, the last axis fastest).
  std::vector<long> grid_indices(long index) const;

 private:
  const Plan* plan_;
  long size_ = 0;
  std::vector<std::string> dimension_names_;
  std::vector<std::vector<double>> dimension_values_;
  std::vector<std::vector<std::string>> dimension_labels_;
  std::vector<std::string> parameter_names_;
  std::vector<std::vector<double>> list_values_;  // list: parameter_values() of every point
};

}  // namespace impactid
