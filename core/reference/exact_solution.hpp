// The exact (d'Alembert) solution of the rod impact for the contact node: the rod arrives at
// t_impact = gap/v0, a compression wave runs to the free end and back in 2L/c, and the rod
// leaves the wall with −v0, unstrained.
//   pressure:      ρ·c·v0 on (t_impact, t_impact + 2L/c), 0 otherwise
//   velocity:      +v0 before, 0 during, −v0 after
//   displacement:  v0·t before, gap during, gap − v0·(t − t_release) after
// At a jump the one-sided limits differ; at_sample() returns their mean when a sample falls on
// the jump within 1e-6·Δt.
//
// With a far wall (RodScene::far_gap = g0) the motion is periodic. Write V = |v0|, D = 2L/c and
// F = (gap + g0)/V, the rigid flight between the walls. A contact with either wall lasts D and
// returns the rod unstrained with its velocity reversed (the single-wall solution above, at each
// wall), so one period T = 2D + 2F is, from the start of a main-wall contact (phase τ = 0):
//   [0, D)            main contact:  p = ρcV, v_n = 0,  u_n = gap
//   [D, D+F)          flight back:   p = 0,   v_n = −V, u_n = gap − V·(τ − D)
//   [D+F, D+F+D/2)    far contact, until its wave reaches node n: v_n = −V, u_n = −g0 − V·(τ−D−F)
//   [D+F+D/2, 2D+F)   far contact, after: v_n = +V, u_n = −g0 − V·D/2 + V·(τ − D − F − D/2)
//   [2D+F, T)         flight forward: v_n = +V, u_n = −g0 + V·(τ − 2D − F)
// (during the far contact node 0 rests on the far wall, node n is free and first keeps −V, then
// gets +V when the reflected compression wave arrives, L/c after the far impact). The first
// impact is at the main wall at gap/V when v0 > 0, at the far wall at g0/V when v0 < 0; before it
// the rod flies rigidly, u = v0·t. With v0 = 0 nothing moves. Jumps (averaged as above) are at
// τ = 0, D and D + F + D/2, and at the first impact.
//
// Thread safety: a value; const methods only.
#pragma once

#include <cmath>

#include "core/model/rod_scene.hpp"

namespace impactid {

struct ContactNodeValues {
  double pressure;      ///< [MPa]
  double velocity;      ///< [mm/s], positive toward the wall
  double displacement;  ///< [mm]
};

class RodImpactExact {
 public:
  explicit RodImpactExact(const RodScene& scene);

  /// First impact at the main wall, and its end (+inf without one).
  double impact_time() const { return impact_time_; }
  double release_time() const { return release_time_; }
  /// With a far wall: the period 2D + 2F of the motion [s]; +inf without one (or v0 = 0).
  double period() const { return period_; }

  /// Values at time t, with the mean of the one-sided limits on a jump within `jump_tolerance`.
  /// Inline for its common case (one wall, away from a jump): the indicators call it at every
  /// sample of every sweep point.
  ContactNodeValues at(double t, double jump_tolerance) const {
    if (!two_walls_ && std::abs(t - impact_time_) > jump_tolerance &&
        std::abs(t - release_time_) > jump_tolerance) {
      return one_sided(t, true);
    }
    return at_jump_or_two_walls(t, jump_tolerance);
  }
  /// The sampling convention of the indicators: t_i = i·Δt, jumps within 1e-6·Δt averaged.
  ContactNodeValues at_sample(long i) const { return at(i * dt_, 1e-6 * dt_); }

 private:
  /// One wall: the solution on one side of each jump (on a jump, its left or right limit).
  ContactNodeValues one_sided(double t, bool from_left) const {
    const auto before = [&](double jump) { return from_left ? t <= jump : t < jump; };
    if (before(impact_time_)) return {0.0, velocity_, velocity_ * t};
    if (before(release_time_)) return {pressure_, 0.0, gap_};
    return {0.0, -velocity_, gap_ - velocity_ * (t - release_time_)};
  }
  ContactNodeValues at_jump_or_two_walls(double t, double jump_tolerance) const;
  ContactNodeValues two_walls_at(double t, double jump_tolerance) const;
  /// The two-wall motion at phase τ in [0, T], from the left or the right of τ.
  ContactNodeValues two_walls_phase(double tau, bool from_left) const;

  double velocity_, gap_, pressure_, dt_;
  double impact_time_, release_time_;
  bool two_walls_ = false;
  double far_gap_ = 0.0, speed_ = 0.0, contact_ = 0.0, flight_ = 0.0;
  double period_ = 0.0;        // T = 2D + 2F
  double first_impact_ = 0.0;  // at either wall
  double phase_origin_ = 0.0;  // t at which τ = 0 (may lie before t = 0)
};

}  // namespace impactid
