// The exact solution of the bouncing bar: the second 1D benchmark of D. Doyen, A. Ern &
// S. Piperno, "Time-integration schemes for the finite element dynamic Signorini problem",
// SIAM J. Sci. Comput. 33(1):223–249 (2011), doi:10.1137/100791440: an elastic bar falls under
// gravity onto rigid ground and bounces. Derived here by characteristics, as follows; the
// literature's period 16L/c comes out.
//
// Problem. A bar 0 <= x <= L (E, ρ, c = √(E/ρ)), x upward from its lower end, obeys
// ρ·u_tt = E·u_xx − ρg; its top is free (σ(L, t) = 0, σ = E·u_x, tension positive) and its lower
// end meets the ground, initially d below it (Signorini):
//   d + u(0, t) >= 0,   p(t) = −σ(0, t) >= 0,   p(t)·(d + u(0, t)) = 0.
// It is released at rest and unstressed. A free bar under a uniform body force stays unstressed
// (σ = 0 solves the free-free problem), so it falls rigidly, u = −g·t²/2, and the gap closes at
// t_f = √(2d/g). The benchmark takes t_f = 3L/c, i.e. d = g·(3L/c)²/2, and L = 10, E = 900,
// ρ = 1, g = 10 (the defaults of BouncingBarParams): c = 30, t_f = 1, d = 5, impact speed 10.
// Any L, E, ρ, g > 0 scale the same solution; another ratio t_f·c/L is a different solution and
// is not covered.
//
// Falling frame. û = u + g·t²/2 solves the wave equation without body force, and the ground
// becomes an obstacle rising at b(t) = g·t²/2 − d with velocity g·t. The Riemann invariants
// ŵ± = v̂ ∓ σ/(ρc) (v̂ = û_t) travel unchanged along dx/dt = ±c. The free top reflects ŵ− = ŵ+.
// The lower end emits ŵ+ from the incoming ŵ−: free (σ = 0) it moves at v̂ = ŵ− and emits
// ŵ+ = ŵ−; held (v̂ = g·t, at rest on the ground) it emits ŵ+ = 2g·t − ŵ− and presses with
// p = ρc·(g·t − ŵ−), so it stays held while ŵ− <= g·t and lets go when ŵ− exceeds it.
//
// Units D = L/c (time), gD (velocity), gD² (displacement), ρgL = ρc·gD (stress); τ = t/D,
// ξ = x/L. Let A(s) be the ŵ+ that the lower end emits at τ = s (in gD); the ŵ− arriving there at
// s is A(s − 2) (its reflection at the top). So A(s) = A(s − 2) while free and
// A(s) = 2s − A(s − 2) while held, with p = ρgL·(s − A(s − 2)). Walking from A = 0 (rest):
//   (0, 3)    A = 0: the rigid fall; the gap closes at τ = 3 with the bar at −3gD;
//   (3, 5)    held: A = 2s, p = ρgL·τ, from 3ρgL (= ρc·3gD, the rod on a wall) up to 5ρgL, as
//             gravity keeps accelerating the part of the bar the wave has not reached;
//   at 5      the arriving ŵ− = A(3+) = 6 exceeds 5: the end lets go (at +gD);
//   (5, 11)   free: A = 2s − 4, 2s − 8, 2s − 12 on (5, 7), (7, 9), (9, 11); the bar flies
//             vibrating, the end's gap (in gD²) is (τ − 3)(τ − 5)/2, (τ² − 16τ + 71)/2 >= 3.5,
//             (τ − 11)(τ − 13)/2, and closes at τ = 11;
//   (11, 13)  held: the arriving ŵ− = 2s − 16 gives A = 16 and p = ρgL·(16 − τ), from 5ρgL down
//             to 3ρgL;
//   at 13     ŵ− = A(11+) = 16 exceeds 13: the end lets go. A = 16 from s = 11 on, so the bar
//             carries ŵ± = 16 everywhere: unstressed, rigid, at (16 − τ)·gD. It leaves at
//             +3gD, rises to the apex at τ = 16 and lands at τ = 19 at −3gD: the state of
//             τ = 3.
// The motion is periodic with period 16L/c and starts at its apex (τ = 0 is τ = 16 of the
// previous period); per period, two contact episodes of 2L/c each, [3D, 5D] and [11D, 13D],
// each with impulse 8ρgL·D (the first leaves the bar vibrating, the second takes the vibration
// back). Benchmark numbers: period 16/3, contacts [1, 5/3] and [11/3, 13/3] + 16k/3, pressure
// 300 → 500 and 500 → 300, impulse 800/3 each.
//
// Closed form. With τ taken mod 16, û = F(τ − ξ) + F(τ + ξ − 2) satisfies the free top
// identically, and F' = A/2:
//   u(x, t) = gD²·[F(τ − ξ) + F(τ + ξ − 2) − τ²/2],
//   v(x, t) = gD·[½A(τ − ξ) + ½A(τ + ξ − 2) − τ],
//   σ(x, t) = ρgL·½·[A(τ + ξ − 2) − A(τ − ξ)],
// on s in [−2, 16]:
//   A(s) = 0, 2s, 2s − 4, 2s − 8, 2s − 12, 16   for s < 3, in (3, 5), (5, 7), (7, 9), (9, 11), >
//   11, F(s) = 0, (s² − 9)/2, (s² − 4s + 11)/2, (s² − 8s + 39)/2, (s² − 12s + 75)/2, 8s − 56.
// At the lower end (τ mod 16; u in gD², v in gD, p in ρgL):
//   [0, 3]    u = −τ²/2,               v = −τ,       p = 0
//   [3, 5]    u = −9/2 (= −d),         v = 0,        p = τ
//   [5, 7]    u = (τ² − 8τ + 6)/2,     v = τ − 4,    p = 0
//   [7, 9]    u = (τ² − 16τ + 62)/2,   v = τ − 8,    p = 0
//   [9, 11]   u = (τ² − 24τ + 134)/2,  v = τ − 12,   p = 0
//   [11, 13]  u = −9/2,                v = 0,        p = 16 − τ
//   [13, 16]  u = −(16 − τ)²/2,        v = 16 − τ,   p = 0
// (v jumps by −4gD at 7 and 9, where the front the end emitted when it let go at 5 comes back
// from the top, twice; it comes back a third time at 11, with the second impact). So v and σ are
// piecewise linear and u piecewise quadratic in x and t, with u_tt = c²·u_xx − g off the kinks.
// The energy, kinetic + strain + gravitational with the ground as zero height,
//   ∫ [½ρv² + σ²/(2E) + ρg·(d + x + u)] dx = ρgL·(d + L/2)   (1000 for the benchmark),
// is conserved: the ground does no work, as the end is at rest while pressed.
//
// Signs: x, u and v point up, away from the ground (as ClampedBarExact's away from its
// obstacle); the pressure is compressive-positive. v and σ jump across the characteristics
// where A jumps, at s = 3, 5, 7, 9, 11 (mod 16); where an argument of A lies within
// jump_tolerance (in time) of one, A takes the mean of its one-sided limits, so a value on one
// jump line is the mean of its two limits, the convention of RodImpactExact::at.
//
// Thread safety: a value; const methods only.
#pragma once

#include <optional>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/reference/bar_exact_values.hpp"
#include "core/reference/exact_solution.hpp"

namespace impactid {

/// The bar and gravity; the defaults are the benchmark's. Any consistent units. The drop height
/// is not a parameter: it is d = g·(3L/c)²/2, the benchmark's fall of 3L/c.
struct BouncingBarParams {
  double length = 10.0;           ///< L, > 0 and finite
  double youngs_modulus = 900.0;  ///< E, > 0 and finite
  double density = 1.0;           ///< ρ, > 0 and finite
  double gravity = 10.0;          ///< g, > 0 and finite, pointing down (−x)
};

/// First invalid field, or nothing.
std::optional<ParameterError> validate(const BouncingBarParams& params);

class BouncingBarExact {
 public:
  /// Throws std::invalid_argument when validate(params) fails.
  explicit BouncingBarExact(const BouncingBarParams& params = {});

  const BouncingBarParams& params() const { return params_; }
  double wave_speed() const { return speed_; }                 ///< c = √(E/ρ)
  double period() const { return 16.0 * transit_; }            ///< 16L/c
  double fall_time() const { return 3.0 * transit_; }          ///< 3L/c, the first impact
  double initial_gap() const { return gap_; }                  ///< d = g·(3L/c)²/2
  double energy_constant() const { return energy_constant_; }  ///< ρgL·(d + L/2)

  /// u(x, t) for x in [0, L] (std::out_of_range outside) and any finite t (periodic).
  double displacement(double x, double t) const;
  /// u, v and σ at (x, t); v and σ averaged on a jump line within jump_tolerance (in time).
  BarPointValues point(double x, double t, double jump_tolerance) const;
  /// The lower end x = 0: p = −σ(0, t) >= 0, v(0, t) and u(0, t) (from the release position, up
  /// positive; the ground is at u = −d); on a jump within jump_tolerance, the mean of the limits.
  ContactNodeValues at(double t, double jump_tolerance) const;
  /// Whether the gap is closed at t (up to round-off at an episode's ends): t mod 16L/c in [3L/c,
  /// 5L/c] or [11L/c, 13L/c].
  bool in_contact(double t) const;
  /// The contact episodes that start in [0, t_end] (t_end >= 0 and at most 10^7 periods,
  /// std::invalid_argument otherwise); one still open at t_end ends there, with its impulse up to
  /// t_end.
  std::vector<ContactEpisode> episodes(double t_end) const;
  /// Kinetic + strain + gravitational energy at t (see above), integrated over the field's
  /// pieces by the two-point Gauss rule, exact for their quadratics (not the constant: the
  /// check of the field).
  double energy(double t) const;

 private:
  BouncingBarParams params_;
  double speed_, transit_;  // c, D = L/c
  double velocity_scale_;   // gD
  double length_scale_;     // gD²
  double stress_scale_;     // ρgL
  double gap_;              // d
  double energy_constant_;  // ρgL·(d + L/2)
};

}  // namespace impactid
