#include "study/plan/work_precision_points.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace impactid {

std::optional<ParameterError> assign_work_precision_point(const Plan& plan, long method,
                                                          long elements, double courant,
                                                          SimulationSettings& settings) {
  settings = plan.base;
  settings.method = plan.work_precision.methods[static_cast<std::size_t>(method)].settings;
  std::optional<ParameterError> error;
  if (settings.model) {
    // A model's mesh is the user's: `elements` is its DOF count (one value), and the Courant
    // number sets the step in place of the scene file's dt.
    settings.scene.dt.reset();
  } else if (settings.bodies) {
    // A scene of bodies: `elements` is the whole scene's, and each segment keeps its share of
    // the [scene] mesh (rounded, at least one element).
    long total = 0;
    for (const Body& body : settings.bodies->bodies) {
      for (const Segment& segment : body.segments) total += segment.elements;
    }
    for (Body& body : settings.bodies->bodies) {
      for (Segment& segment : body.segments) {
        const double share = static_cast<double>(segment.elements) * static_cast<double>(elements) /
                             static_cast<double>(total);
        segment.elements = static_cast<int>(std::max(1.0, std::min(std::round(share), 2e9)));
      }
    }
  } else {
    error = assign(settings, "elements", static_cast<double>(elements));
  }
  if (!error) error = assign(settings, "courant", courant);
  return error;
}

SimulationSettings work_precision_settings(const Plan& plan, long method, long elements,
                                           double courant) {
  SimulationSettings settings;
  // load_plan() assigned and built these same values: an error here is a bug.
  [[maybe_unused]] const auto error =
      assign_work_precision_point(plan, method, elements, courant, settings);
  assert(!error);
  return settings;
}

long work_precision_index(const WorkPrecisionStudy& study, long method, long elements_index,
                          long courant_index) {
  const auto n_elements = static_cast<long>(study.elements.size());
  const auto n_courant = static_cast<long>(study.courant.size());
  return (method * n_elements + elements_index) * n_courant + courant_index;
}

}  // namespace impactid
