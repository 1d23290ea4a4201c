#include "core/reference/exact_solution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace impactid {

RodImpactExact::RodImpactExact(const RodScene& scene) {
  const RodSceneDerived d = derive(scene);
  velocity_ = scene.velocity;
  gap_ = scene.gap;
  pressure_ = d.pressure_scale;
  dt_ = d.time_step;
  impact_time_ = d.impact_time;
  release_time_ = d.impact_time + d.contact_duration;
  period_ = std::numeric_limits<double>::infinity();
  if (scene.far_gap) {
    two_walls_ = true;
    far_gap_ = *scene.far_gap;
    speed_ = std::abs(scene.velocity);
    contact_ = d.contact_duration;
    if (speed_ > 0.0) {
      flight_ = (gap_ + far_gap_) / speed_;
      period_ = 2.0 * contact_ + 2.0 * flight_;
      if (scene.velocity > 0.0) {
        first_impact_ = gap_ / speed_;
        phase_origin_ = first_impact_;
      } else {
        // The far contact starts at τ = D + F.
        first_impact_ = far_gap_ / speed_;
        phase_origin_ = first_impact_ - (contact_ + flight_);
      }
    }
  }
}

ContactNodeValues RodImpactExact::two_walls_phase(double tau, bool from_left) const {
  const auto before = [&](double boundary) { return from_left ? tau <= boundary : tau < boundary; };
  const double d = contact_, f = flight_, v = speed_;
  if (tau == 0.0 && from_left) tau = period_;  // the end of the previous period
  if (before(d)) return {pressure_, 0.0, gap_};
  if (before(d + f)) return {0.0, -v, gap_ - v * (tau - d)};
  if (before(d + f + 0.5 * d)) return {0.0, -v, -far_gap_ - v * (tau - d - f)};
  if (before(2.0 * d + f)) return {0.0, v, -far_gap_ - v * (0.5 * d) + v * (tau - d - f - 0.5 * d)};
  if (before(period_)) return {0.0, v, -far_gap_ + v * (tau - 2.0 * d - f)};
  return {pressure_, 0.0, gap_};  // τ = T from the right: the next main contact
}

ContactNodeValues RodImpactExact::two_walls_at(double t, double jump_tolerance) const {
  const auto mean = [](const ContactNodeValues& a, const ContactNodeValues& b) {
    return ContactNodeValues{0.5 * (a.pressure + b.pressure), 0.5 * (a.velocity + b.velocity),
                             0.5 * (a.displacement + b.displacement)};
  };
  if (speed_ == 0.0) return {0.0, 0.0, 0.0};
  const ContactNodeValues flying{0.0, velocity_, velocity_ * t};
  if (t < first_impact_ - jump_tolerance) return flying;
  const double tau_first = velocity_ > 0.0 ? 0.0 : contact_ + flight_;
  if (std::abs(t - first_impact_) <= jump_tolerance) {
    return mean(ContactNodeValues{0.0, velocity_, velocity_ * first_impact_},
                two_walls_phase(tau_first, false));
  }
  const double since = t - phase_origin_;
  double tau = since - period_ * std::floor(since / period_);
  if (tau <= jump_tolerance) tau += period_;  // near τ = 0: treat as the end of a period
  for (const double jump : {contact_, contact_ + flight_ + 0.5 * contact_, period_}) {
    if (std::abs(tau - jump) <= jump_tolerance) {
      return mean(two_walls_phase(jump, true), two_walls_phase(jump, false));
    }
  }
  return two_walls_phase(std::min(tau, period_), true);
}

// at()'s other cases: a far wall, or a sample on a jump.
ContactNodeValues RodImpactExact::at_jump_or_two_walls(double t, double jump_tolerance) const {
  if (two_walls_) return two_walls_at(t, jump_tolerance);
  const bool on_jump =
      std::abs(t - impact_time_) <= jump_tolerance || std::abs(t - release_time_) <= jump_tolerance;
  if (!on_jump) return one_sided(t, true);
  // Evaluate the limits at the jump itself, so that the mean is exact.
  const double jump = std::abs(t - impact_time_) <= jump_tolerance ? impact_time_ : release_time_;
  const ContactNodeValues left = one_sided(jump, true);
  const ContactNodeValues right = one_sided(jump, false);
  return {0.5 * (left.pressure + right.pressure), 0.5 * (left.velocity + right.velocity),
          0.5 * (left.displacement + right.displacement)};
}

}  // namespace impactid
