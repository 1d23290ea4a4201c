// The points of a grid or list plan, each identified by its flat index: row-major over the
// grid axes in file order (the last axis varies fastest), or the position in a list. The
// index is all a worker needs to rebuild a point, so a set of indices can be handed to
// another thread, process or cluster job.
#pragma once

#include <string>
#include <vector>

#include "study/plan.hpp"
#include "study/simulation_settings.hpp"

namespace impactid {

class PointSet {
 public:
  explicit PointSet(const Plan& plan);  ///< grid or list plans

  long size() const { return size_; }
  /// Grid: one dimension per independent axis. List: one dimension "point" = 0..K−1.
  const std::vector<std::string>& dimension_names() const { return dimension_names_; }
  const std::vector<std::vector<double>>& dimension_values() const { return dimension_values_; }
  std::vector<long> shape() const;

  /// Parameters that vary between points (grid axes, coupled axes, list keys), numeric ones.
  const std::vector<std::string>& parameter_names() const { return parameter_names_; }
  /// Their values at a point, in parameter_names() order.
  std::vector<double> parameter_values(long index) const;

  /// Base settings with the point's values applied. Points were checked by load_plan(), so
  /// this does not fail for a loaded plan.
  SimulationSettings settings(long index) const;

 private:
  const Plan* plan_;
  long size_ = 0;
  std::vector<std::string> dimension_names_;
  std::vector<std::vector<double>> dimension_values_;
  std::vector<std::string> parameter_names_;
};

}  // namespace impactid
