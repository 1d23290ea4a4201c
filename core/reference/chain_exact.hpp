// The exact solution of a Scene (core/model/scene.hpp) — a line of elastic rods with unilateral
// contacts between neighbours and optional rigid walls — for the continuous wave equation (not the
// FE model), by an event-driven method of characteristics. It is the reference for scenes of
// several bodies as RodImpactExact (core/reference/exact_solution.hpp) is for one rod and its
// walls.
//
// References: K. F. Graff, Wave Motion in Elastic Solids, Oxford 1975, ch. 2 (d'Alembert's
// solution of the rod, reflection and transmission at a change of section, impact of rods);
// W. Goldsmith, Impact, Arnold 1960, ch. 4 (collinear impact of rods); the split-Hopkinson bar
// literature for the same one-dimensional wave bookkeeping (e.g. W. W. Chen & B. Song,
// Split Hopkinson (Kolsky) Bar, Springer 2011, ch. 1–2).
//
// Characteristic variables. In a uniform segment (length L, E, ρ, A, c = √(E/ρ), impedance
// Z = ρcA) the velocity v and the axial force N (tension positive) are
//   v = r + l,   N = Z·(l − r),
// with r(x − ct) the right-going and l(x + ct) the left-going component. Bodies start unstressed
// at their own velocity v0, so r = l = v0/2 in each of their segments, and both stay piecewise
// constant in their characteristic coordinate. (A scene with an initial strain or a clamped end
// is not solved here: the constructor refuses it.) Energy and momentum per unit length separate,
//   ½ρA v² + N²/(2EA) = ρA·(r² + l²),   ρA v = ρA·(r + l),
// because Z²/(EA) = ρA.
//
// Boundary points. Every segment end is one: what a point emits into a segment at time t
// arrives at the segment's other end at t + L/c. A point's outgoing values are computed from its
// incoming ones (r arriving through the segment on its left, l through the segment on its right)
// and from its contact state, so every value is piecewise constant in time and changes only at
// events: an arrival that changes an incoming value, or a gap that closes.
//   Junction of segments a (left) and b (right), welded: v and N continuous give
//     v = 2·(Z_a·r_a + Z_b·l_b)/(Z_a + Z_b),
//     l_a = R_a·r_a + T_ba·l_b,   r_b = T_ab·r_a + R_b·l_b,
//     R_a = (Z_a − Z_b)/(Z_a + Z_b) = −R_b,  T_ab = 2Z_a/(Z_a + Z_b),  T_ba = 2Z_b/(Z_a + Z_b)
//   (reflection and transmission coefficients for velocity; equal impedances give R = 0, T = 1
//   exactly, so a uniform rod cut into segments stays exact to the bit).
//   Free end: N = 0, the wave reflects with its velocity unchanged: l_a = r_a (right end),
//     r_b = l_b (left end); the end node moves at its "free velocity" 2·r_a or 2·l_b.
//   Rigid wall, closed: v = 0, l_a = −r_a and λ = 2·Z_a·r_a (right wall), r_b = −l_b and
//     λ = −2·Z_b·l_b (left wall).
//   Two bodies in contact, closed: a welded junction of the left body's last segment (a) and the
//     right body's first (b), with λ = −N = Z_a·Z_b/(Z_a + Z_b)·(v_a − v_b), v_a = 2·r_a and
//     v_b = 2·l_b being the two ends' free velocities (a wall's is 0).
// So a contact's welded force is its reduced impedance times the approach velocity of its free
// ends: at gap 0 the contact is closed exactly when that approach velocity is positive (λ > 0),
// and open otherwise; with λ = 0 both choices give the same motion, and open is taken, so no
// Zeno chatter arises at zero relative velocity. An open contact's gap changes at the (piecewise
// constant) relative velocity of its two free ends, so its closing time is exact.
//
// Closed forms this reproduces (Graff ch. 2, Goldsmith ch. 4): a rod at v0 on a rigid wall presses
// with ρcA·v0 for 2L/c and leaves at −v0 unstrained; two equal rods (striker at v0, target at
// rest) touch with ρcA·v0/2 for 2L/c, the striker stops and the target leaves at v0; a shorter
// striker (L1 < L2, same material and area) presses with ρcA·v0/2 for 2L1/c and is at rest after;
// two equal rods at ±v0 behave as one rod on a wall.
//
// Numerics. Event times are sums of travel times L/c, so times that agree in exact arithmetic
// (the equal-rods case has coincident arrivals at both sides of a contact) may differ by
// round-off. Events whose times lie within ChainExactOptions::merge_tolerance·t_end of the
// earliest pending one are processed together, at that earliest time: this moves a front by at
// most that amount and avoids needle pulses of round-off width. An outgoing value that changes
// by less than ChainExactOptions::value_tolerance·(largest |v0|) keeps its old value, so
// round-off does not seed fronts of size ~1e-16 that multiply at every junction. The number of
// fronts up to t_end is finite, but it grows geometrically with the number of junctions of
// incommensurate travel times; more than ChainExactOptions::max_events events throw
// std::runtime_error.
//
// Output per contact k (the order of scene_contacts()): its force λ_k(t) >= 0 (piecewise
// constant; pressure = λ/SceneContact::area), the velocity of its node (the left body's end node;
// for the left wall body 0's first node; piecewise constant, +x positive — unlike
// RodImpactExact's "toward the wall", so at the left wall the sign is reversed) and that node's
// displacement (piecewise linear and continuous, from the initial position). While a body rests
// on a wall its node's displacement is the wall's position exactly (gap, or −gap on the left).
//
// Thread safety: a value; const methods only. The solve happens in the constructor.
#pragma once

#include <span>
#include <vector>

#include "core/model/scene.hpp"
#include "core/reference/exact_solution.hpp"

namespace impactid {

struct ChainExactOptions {
  /// Events within merge_tolerance·t_end of each other are one event (see the header comment).
  /// Dimensionless, >= 0; default 1e-12, some 10^4 ulps of the largest time.
  double merge_tolerance = 1e-12;
  /// Changes of an emitted wave value below value_tolerance·max|v0| are dropped. Dimensionless,
  /// >= 0; default 1e-13.
  double value_tolerance = 1e-13;
  /// Most events (arrivals and gap closings) to process up to t_end; more throw
  /// std::runtime_error. >= 1; default 1e7 (about 0.5 GB of wave history at worst).
  long max_events = 10'000'000;
};

/// Total momentum and energy of all bodies at one time, integrated over the segments' waves.
struct ChainBalance {
  double momentum;  ///< Σ ∫ ρA·v dx [t·mm/s = N·s]
  double energy;    ///< Σ ∫ ρA·(r² + l²) dx, kinetic + strain [mJ = N·mm]
};

class ChainExact {
 public:
  /// Solves `scene` from t = 0 up to t_end [s] (finite, >= 0). Throws std::invalid_argument if
  /// the scene fails validate(), its bodies do not start free and unstrained (bodies_start_free:
  /// a clamped wall or an initial displacement, which the waves above leave out), or an option
  /// or t_end is out of range, and std::runtime_error if
  /// more than options.max_events events occur. To sample at t_i = i·Δt, i = 1..N, pass
  /// t_end = N·Δt (SceneDerived::step_count can put t_N slightly past the scene's t_end).
  ChainExact(const Scene& scene, double t_end, const ChainExactOptions& options = {});

  int contact_count() const { return static_cast<int>(contacts_.size()); }
  double end_time() const { return t_end_; }

  /// Values of contact k at t in [0, t_end] (std::out_of_range outside, within the merge
  /// tolerance): pressure λ/area [MPa], the node's velocity [mm/s] and displacement [mm]. On a
  /// jump within jump_tolerance [s] the mean of the one-sided limits (the displacement is
  /// continuous), the convention of RodImpactExact::at. A binary search per call.
  ContactNodeValues at(int contact, double t, double jump_tolerance) const;
  /// Force λ_k [N] at t, the one-sided value from the right (no averaging).
  double force(int contact, double t) const;

  /// Jump times of contact k's pressure or velocity, increasing [s]; a jump at t = 0 is listed
  /// when the contact is closed from the start.
  std::span<const double> jumps(int contact) const;

  /// Momentum and energy of the bodies at t in [0, t_end], from the wave states of every
  /// segment: the check of the scattering rules (energy is conserved; momentum changes only by
  /// the walls' impulses).
  ChainBalance balance_at(double t) const;
  /// The same for one body (its index in Scene::bodies).
  ChainBalance body_balance_at(int body, double t) const;

  /// Events processed (wave arrivals that reached a point, gap closings).
  long events() const { return events_; }

 private:
  // A piecewise-constant function of time: value[i] holds on [time[i], time[i+1]).
  struct History {
    std::vector<double> time, value;
  };
  struct SegmentWaves {
    double travel_time;   // L/c [s]
    double impedance;     // Z = ρcA [N·s/mm]
    int body;             // index in Scene::bodies
    History right_going;  // r emitted at the left end, from time −inf (the initial v0/2)
    History left_going;   // l emitted at the right end, likewise
  };
  // One contact's output: entry i holds from time[i] until time[i+1].
  struct ContactTrace {
    double area;
    std::vector<double> time;
    std::vector<double> force, velocity, displacement;  // displacement at time[i]
  };

  struct Solver;  // the event loop (chain_exact.cpp); fills the members below

  ContactNodeValues entry_values(const ContactTrace& trace, std::size_t i, double t) const;
  void require_in_time(double t, const char* what) const;
  ChainBalance balance_of(double t, int body) const;  // body −1: all

  double t_end_ = 0.0;
  double time_tolerance_ = 0.0;
  long events_ = 0;
  std::vector<SegmentWaves> segments_;
  std::vector<ContactTrace> contacts_;
};

}  // namespace impactid
