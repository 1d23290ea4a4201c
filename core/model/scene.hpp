// An impact scene of several bodies (issue 18): a line of elastic rods along x, left to right,
// each rod a chain of uniform segments, with a unilateral contact between each pair of
// neighbours and optional rigid walls at both ends.
//
//   [left wall] gap  body 0 (segments 0..)  gap  body 1  …  body m−1  gap  [right wall]
//
// Units: N, mm, s, t (tonne), as RodScene. Velocities are positive toward +x (to the right).
// Every body moves rigidly with its own velocity until its first contact; displacements are
// measured from the initial positions.
//
// Contacts, in this order (scene_contacts): the left wall's, one between each pair of
// neighbouring bodies, the right wall's. Each is a Lagrange-multiplier constraint
//   left wall:    −u_first(0) − gap <= 0,            force +λ on the first node of body 0
//   body pair:    u_last(i) − u_first(i+1) − gap <= 0, −λ on body i's last node, +λ on body
//                                                      i+1's first node
//   right wall:   u_last(m−1) − gap <= 0,            force −λ on the last node of body m−1
// with λ >= 0 the compressive contact force [N]. A contact's pressure is λ divided by the area
// of the left body's end segment (for the left wall, body 0's first segment); its velocity and
// displacement are those of the left body's end node (for the left wall, body 0's first node).
//
// The paper's scene is one body of one segment with a right wall; RodScene is that shorthand
// (with a second wall behind the rod when far_gap is set), and to_scene() converts it.
//
// Thread safety: values; const functions only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/model/rod_scene.hpp"

namespace impactid {

/// A uniform piece of a rod. Defaults are the paper's rod.
struct Segment {
  double length = 20.0;          ///< [mm], > 0
  int elements = 200;            ///< >= 1; h = length/elements
  double youngs_modulus = 90.0;  ///< E [MPa], > 0
  double density = 7.85e-9;      ///< ρ [t/mm³], > 0
  double area = 1.0;             ///< A [mm²], > 0

  bool operator==(const Segment&) const = default;
};

/// One rod: segments from left to right, welded together; its nodes are numbered left to right.
struct Body {
  std::string name;               ///< unique within the scene; letters, digits and '_'
  double velocity = 0.0;          ///< initial velocity of every node [mm/s], +x positive, finite
  double gap = 0.0;               ///< gap to the body (or the wall) on its left [mm], >= 0
  std::vector<Segment> segments;  ///< at least one

  bool operator==(const Body&) const = default;
};

struct Wall {
  double gap = 0.0;  ///< gap between the wall and the end node next to it [mm], >= 0

  bool operator==(const Wall&) const = default;
};

struct Scene {
  std::vector<Body> bodies;  ///< at least one, left to right
  /// Optional rigid walls. The left wall's gap is Wall::gap; body 0's own gap must be 0 (a scene
  /// file's `gap` on its first body is the left wall's gap, and the parser puts it there).
  std::optional<Wall> left_wall, right_wall;
  MassMatrix mass = MassMatrix::lumped;
  double rayleigh_mass = 0.0;       ///< a0 in C = a0·M + a1·K [1/s], >= 0
  double rayleigh_stiffness = 0.0;  ///< a1 in C = a0·M + a1·K [s], >= 0
  /// Courant number c·Δt/h of the segment with the smallest h/c; used when dt is not given. > 0.
  double courant = 0.5;
  std::optional<double> dt;  ///< Δt [s]; overrides courant
  /// End time [s]; default: the first contact's closing time + 1.5 × the longest two-way
  /// transit time Σ 2·L_s/c_s of a body that takes part in that contact.
  std::optional<double> t_end;
  /// Name of the primary contact (scene_contacts): its indicators are the ones a sweep stores
  /// as eps_p, eps_v, … Default: the first contact to close (the first in order on a tie).
  std::optional<std::string> primary_contact;

  bool operator==(const Scene&) const = default;
};

/// The one-body shorthand: the rod of `rod` with a right wall at `gap` and, when far_gap is set,
/// a left wall at far_gap; the body is named "rod" and the right wall is the primary contact.
Scene to_scene(const RodScene& rod);

/// The other way: the rod's shorthand of a scene in the paper's form (one body of one segment
/// and a right wall, nothing else), with the scene's end time stated, whose run is the scene's
/// bit for bit (the same matrices, step, time grid and free flight: core/model/scene_assembly.hpp).
/// Sweeps run such scenes in the rod's batched kernel. Nothing for any other scene.
std::optional<RodScene> as_rod(const Scene& scene);

enum class ContactKind { left_wall, bodies, right_wall };

/// One contact of a scene, with what identifies it in results and where it acts.
struct SceneContact {
  std::string name;  ///< "wall_left", "wall_right", or "<left body>-<right body>"
  ContactKind kind;
  int left_body;   ///< body on the left; −1 for the left wall
  int right_body;  ///< body on the right; −1 for the right wall
  double gap;      ///< [mm]
  double area;     ///< pressure = λ / area [mm²]
  /// Time at which the gap closes if every body flew rigidly (+inf if it never does) [s].
  double rigid_closing_time;
};
std::vector<SceneContact> scene_contacts(const Scene& scene);

/// First invalid field of the scene, named by its dotted path (`body.striker.segment.1.area`,
/// `wall.left.gap`, `courant`), or nothing.
std::optional<ParameterError> validate(const Scene& scene);

/// Quantities derived from a valid scene, computed in one place.
struct SceneDerived {
  double time_step;           ///< Δt [s]
  double min_h_over_c;        ///< smallest h/c over all segments [s]
  double first_contact_time;  ///< earliest rigid closing time (+inf if no contact closes) [s]
  int primary_contact;        ///< index into scene_contacts()
  double end_time;            ///< t_end [s]
  long step_count;            ///< N = ⌈t_end/Δt − 1e-9⌉; samples t_i = i·Δt, i = 1..N
  double initial_energy;      ///< Σ ½·ρ·A·L·v² [mJ]
  double velocity_scale;      ///< largest |v| of a body [mm/s]
  long nodes;                 ///< Σ (elements + 1) over the bodies
};
SceneDerived derive(const Scene& scene);

/// Two-way transit time Σ 2·L_s/c_s of a body [s].
double transit_time(const Body& body);
/// First node index of each body in the assembled system, and one past the last.
std::vector<long> body_first_nodes(const Scene& scene);

}  // namespace impactid
