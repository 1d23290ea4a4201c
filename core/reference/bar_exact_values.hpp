// What the exact solutions of the 1D bar benchmarks (core/reference/clamped_bar_exact.hpp,
// core/reference/bouncing_bar_exact.hpp) return besides ContactNodeValues (the contact end's
// values, core/reference/exact_solution.hpp): the state of one material point, and one contact
// episode. Units are those of the benchmark's parameters (any consistent set; the published
// benchmarks are dimensionless or give bare numbers). Both are one-dimensional: a stress is a
// force per unit cross-section area, an impulse a stress times a time, an energy one per unit
// area.
#pragma once

namespace impactid {

/// The state of the material point x of a bar at time t; x and every sign along the bar's axis.
struct BarPointValues {
  double displacement;  ///< u(x, t), positive along +x
  double velocity;      ///< v = ∂u/∂t, positive along +x
  double stress;        ///< σ = E·∂u/∂x, tension positive
};

/// One contact episode: a maximal closed interval of time on which the contact end touches the
/// obstacle (gap zero), with the impulse ∫ p dt of the contact pressure p over it.
struct ContactEpisode {
  double start;    ///< time the gap closes
  double end;      ///< time it opens again, >= start
  double impulse;  ///< ∫ p dt over [start, end], per unit area (stress·time), >= 0
};

}  // namespace impactid
