#include "core/exact_solution.hpp"

#include <cmath>

namespace impactid {

RodImpactExact::RodImpactExact(const RodScene& scene) {
  const RodSceneDerived d = derive(scene);
  velocity_ = scene.velocity;
  gap_ = scene.gap;
  pressure_ = d.pressure_scale;
  dt_ = d.time_step;
  impact_time_ = d.impact_time;
  release_time_ = d.impact_time + d.contact_duration;
}

ContactNodeValues RodImpactExact::one_sided(double t, bool from_left) const {
  const auto before = [&](double jump) { return from_left ? t <= jump : t < jump; };
  if (before(impact_time_)) return {0.0, velocity_, velocity_ * t};
  if (before(release_time_)) return {pressure_, 0.0, gap_};
  return {0.0, -velocity_, gap_ - velocity_ * (t - release_time_)};
}

ContactNodeValues RodImpactExact::at(double t, double jump_tolerance) const {
  const bool on_jump = std::abs(t - impact_time_) <= jump_tolerance ||
                       std::abs(t - release_time_) <= jump_tolerance;
  if (!on_jump) return one_sided(t, true);
  // Evaluate the limits at the jump itself, so that the mean is exact.
  const double jump =
      std::abs(t - impact_time_) <= jump_tolerance ? impact_time_ : release_time_;
  const ContactNodeValues left = one_sided(jump, true);
  const ContactNodeValues right = one_sided(jump, false);
  return {0.5 * (left.pressure + right.pressure), 0.5 * (left.velocity + right.velocity),
          0.5 * (left.displacement + right.displacement)};
}

}  // namespace impactid
