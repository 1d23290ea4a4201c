// The exact solution of the clamped bar released onto an obstacle: the first 1D benchmark of
// D. Doyen, A. Ern & S. Piperno, "Time-integration schemes for the finite element dynamic
// Signorini problem", SIAM J. Sci. Comput. 33(1):223–249 (2011), doi:10.1137/100791440, also
// GetFEM's demo_dynamic_contact_1D. Derived here by characteristics, as follows.
//
// Problem. A bar 0 <= x <= L (Young's modulus E, density ρ, c = √(E/ρ)) obeys ρ·u_tt = E·u_xx,
// is clamped at x = L (u(L, t) = 0) and meets a rigid obstacle at x = 0 (Signorini):
//   u(0, t) >= 0,   p(t) = −σ(0, t) >= 0,   p(t)·u(0, t) = 0,
// with σ = E·u_x (tension positive) and p the contact pressure, the Signorini multiplier. It
// starts at rest and uniformly compressed, u(x, 0) = a·(1 − x/L), v(x, 0) = 0, so the contact
// end starts a gap a away from the obstacle. The benchmark is L = E = ρ = 1, a = 1/2 (the
// defaults of ClampedBarParams); the solution below holds for any L, E, ρ, a > 0, scaled.
//
// Characteristics. With v = u_t, the Riemann invariants w± = v ∓ σ/(ρc) travel unchanged along
// dx/dt = ±c. The clamped end reflects w− = −w+ (v = 0). The contact end emits w+ from the
// incoming w−: free (σ = 0) it moves at v = w− and emits w+ = w−; held (u = v = 0) it emits
// w+ = −w− and presses with p = −ρc·w−. So it stays held while w− <= 0 and lets go when w−
// turns positive; it is caught when its gap closes while it moves toward the obstacle.
// Initially w+ = ac/L, w− = −ac/L everywhere. Write V = ac/L and D = L/c:
//   (0, D)    the end is free and moves at w− = −V: it closes the gap a exactly at t = D, and
//             emits w+ = −V;
//   (D, 2D)   w− is still −V (the initial w+, reflected at the clamp): held, p = ρcV = aE/L,
//             emits w+ = +V;
//   (2D, 3D)  w− = +V (the w+ = −V of (0, D), reflected): free, it leaves at +V and reaches
//             u(0) = a at 3D, emitting w+ = +V.
// At 3D the bar again carries w+ = V and w− = −V everywhere with u(0) = a: the initial state.
// The motion is periodic with period 3L/c, with one contact episode [D, 2D] per period.
//
// Closed form. With ξ = x/L and τ = ct/L, the d'Alembert form that vanishes at x = L is
//   u(x, t) = a·[P(τ − ξ) − P(τ + ξ − 2)],
// where P' = ½w+/V is −½ when s mod 3 lies in (0, 1) and +½ when it lies in (1, 3), P(0) = 0:
//   P(s) = k/2 + (|s − 3k − 1| − 1)/2,   k = ⌊s/3⌋   (so P(s + 3) = P(s) + ½).
// Then v = V·[P'(τ − ξ) − P'(τ + ξ − 2)] and σ = −(aE/L)·[P'(τ − ξ) + P'(τ + ξ − 2)]. Over one
// period (τ mod 3) the displacement is piecewise linear in x and t:
//   τ in [0, 1]:  u = a·(1 − max(ξ, τ))
//   τ in [1, 2]:  u = a·max(1 − τ, −ξ, ξ − 1, τ − 2)
//   τ in [2, 3]:  u = a·min(τ − 2, 1 − ξ)
// (the zones of GetFEM's demo agree). At the contact end, by phase:
//   u(0, t) = a·(1 − τ), 0, a·(τ − 2);   v(0, t) = −V, 0, +V;   p(t) = 0, aE/L, 0,
// and the clamp's stress σ(L, t) = −aE/L, +aE/L, −aE/L. Every point carries either |v| = V and
// σ = 0 or v = 0 and |σ| = aE/L, so the energy density ½ρv² + σ²/(2E) is a²E/(2L²) everywhere
// at all times and the energy is a²E/(2L) (per unit area). Each contact episode's impulse is
// (aE/L)·(L/c) = a·ρc. The benchmark's numbers: period 3, contact on [1, 2] + 3k with p = ½,
// impulse ½, energy 1/8.
//
// Signs: x, u and v point from the obstacle into the bar (away from the obstacle), as for the
// left wall of ChainExact (core/reference/chain_exact.hpp) and unlike RodImpactExact's "toward
// the wall"; the pressure is compressive-positive. v and σ jump across the characteristics where
// P' jumps: τ − ξ ≡ 0 or 1 and τ + ξ ≡ 2 or 0 (mod 3). Where an argument of P' lies within
// jump_tolerance (in time) of a jump, P' takes the mean of its one-sided limits, so a value on
// one jump line is the mean of its two limits, the convention of RodImpactExact::at. The
// displacement is continuous and needs no tolerance.
//
// Thread safety: a value; const methods only.
#pragma once

#include <optional>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/reference/bar_exact_values.hpp"
#include "core/reference/exact_solution.hpp"

namespace impactid {

/// The bar and its initial compression; the defaults are the benchmark's. Any consistent units.
struct ClampedBarParams {
  double length = 1.0;          ///< L, > 0 and finite
  double youngs_modulus = 1.0;  ///< E, > 0 and finite
  double density = 1.0;         ///< ρ, > 0 and finite
  double amplitude = 0.5;       ///< a = u(0, 0), the initial gap: u(x, 0) = a·(1 − x/L); > 0
};

/// First invalid field, or nothing.
std::optional<ParameterError> validate(const ClampedBarParams& params);

class ClampedBarExact {
 public:
  /// Throws std::invalid_argument when validate(params) fails.
  explicit ClampedBarExact(const ClampedBarParams& params = {});

  const ClampedBarParams& params() const { return params_; }
  double wave_speed() const { return speed_; }                 ///< c = √(E/ρ)
  double period() const { return 3.0 * transit_; }             ///< 3L/c
  double contact_pressure() const { return pressure_; }        ///< aE/L, while held
  double energy_constant() const { return energy_constant_; }  ///< a²E/(2L), the conserved value

  /// u(x, t) for x in [0, L] (std::out_of_range outside) and any finite t (periodic).
  double displacement(double x, double t) const;
  /// u, v and σ at (x, t); v and σ averaged on a jump line within jump_tolerance (in time).
  BarPointValues point(double x, double t, double jump_tolerance) const;
  /// The contact end x = 0: p = −σ(0, t) >= 0, v(0, t) and u(0, t), +x away from the obstacle;
  /// on a jump within jump_tolerance, the mean of the one-sided limits.
  ContactNodeValues at(double t, double jump_tolerance) const;
  /// Whether the gap is closed at t (up to round-off at an episode's ends): t mod 3L/c in [L/c,
  /// 2L/c].
  bool in_contact(double t) const;
  /// The contact episodes that start in [0, t_end] (t_end >= 0 and at most 10^7 periods,
  /// std::invalid_argument otherwise); one still open at t_end ends there, with its impulse up to
  /// t_end.
  std::vector<ContactEpisode> episodes(double t_end) const;
  /// Kinetic plus strain energy ∫ (½ρv² + σ²/(2E)) dx at t, integrated over the field's pieces
  /// (exact, not the constant a²E/(2L): the check of the field).
  double energy(double t) const;

 private:
  ClampedBarParams params_;
  double speed_, transit_;  // c, L/c
  double velocity_;         // V = ac/L
  double pressure_;         // aE/L
  double energy_constant_;  // a²E/(2L)
};

}  // namespace impactid
