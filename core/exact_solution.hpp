// The exact (d'Alembert) solution of the rod impact for the contact node: the rod arrives at
// t_impact = gap/v0, a compression wave runs to the free end and back in 2L/c, and the rod
// leaves the wall with −v0, unstrained.
//   pressure:      ρ·c·v0 on (t_impact, t_impact + 2L/c), 0 otherwise
//   velocity:      +v0 before, 0 during, −v0 after
//   displacement:  v0·t before, gap during, gap − v0·(t − t_release) after
// At a jump the one-sided limits differ; at_sample() returns their mean when a sample falls on
// the jump within 1e-6·Δt.
//
// Thread safety: a value; const methods only.
#pragma once

#include "core/rod_scene.hpp"

namespace impactid {

struct ContactNodeValues {
  double pressure;      ///< [MPa]
  double velocity;      ///< [mm/s], positive toward the wall
  double displacement;  ///< [mm]
};

class RodImpactExact {
 public:
  explicit RodImpactExact(const RodScene& scene);

  double impact_time() const { return impact_time_; }
  double release_time() const { return release_time_; }

  /// Values at time t, with the mean of the one-sided limits on a jump within `jump_tolerance`.
  ContactNodeValues at(double t, double jump_tolerance) const;
  /// The sampling convention of the indicators: t_i = i·Δt, jumps within 1e-6·Δt averaged.
  ContactNodeValues at_sample(long i) const { return at(i * dt_, 1e-6 * dt_); }

 private:
  ContactNodeValues one_sided(double t, bool from_left) const;

  double velocity_, gap_, pressure_, dt_;
  double impact_time_, release_time_;
};

}  // namespace impactid
