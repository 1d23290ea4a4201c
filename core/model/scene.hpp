// An impact scene of several bodies (issue 18): a line of elastic rods along x, left to right,
// each rod a chain of uniform segments, with a unilateral contact between each pair of
// neighbours and optional rigid walls at both ends.
//
//   [left wall] gap  body 0 (segments 0..)  gap  body 1  …  body m−1  gap  [right wall]
//
// Units: N, mm, s, t (tonne), as RodScene. Velocities are positive toward +x (to the right).
// Displacements are measured from each node's reference position, the one the gaps are measured
// at. A body starts at its own velocity and, by default, undisplaced (then it moves rigidly until
// its first contact); it may start with a displacement field linear in x (Body::displacement), an
// initial strain, and a wall may clamp its end node instead of being a contact (WallKind::clamped:
// u = 0 for all time, the node removed from the assembled system, core/model/scene_assembly.hpp).
// Such a scene is not one whose bodies start free (bodies_start_free), and what assumes they do
// refuses it: the run's filled-in free flight (AssembledScene::rigid_flight), the rod's shorthand
// (as_rod), the exact solution of the chain (core/reference/chain_exact.hpp) and the batched chain
// kernel (core/batch/batched_chain.hpp). Doyen, Ern & Piperno's clamped bar released onto an
// obstacle is such a scene, with an exact solution of its own (core/reference/scene_reference.hpp:
// clamped_bar_params).
//
// Contacts, in this order (scene_contacts): the left wall's, one between each pair of
// neighbouring bodies, the right wall's (a clamped wall is no contact). Each is a
// Lagrange-multiplier constraint
//   left wall:    −u_first(0) − gap <= 0,            force +λ on the first node of body 0
//   body pair:    u_last(i) − u_first(i+1) − gap <= 0, −λ on body i's last node, +λ on body
//                                                      i+1's first node
//   right wall:   u_last(m−1) − gap <= 0,            force −λ on the last node of body m−1
// with λ >= 0 the compressive contact force [N]. A contact's pressure is λ divided by the area
// of the left body's end segment (for the left wall, body 0's first segment); its velocity and
// displacement are those of the left body's end node (for the left wall, body 0's first node).
//
// Gravity (Scene::gravity) is a uniform acceleration g of every body along x, a body force ρ·g per
// unit volume; it must point toward a wall (g < 0: the left one, g > 0: the right one), above
// which the potential energy ρ·|g|·height is counted (core/model/constant_load.hpp). Under it no
// body flies as u = v0·t, so a scene with gravity is not one whose bodies start free
// (bodies_start_free). Doyen, Ern & Piperno's bouncing bar is such a scene, with an exact
// solution of its own (core/reference/scene_reference.hpp: bouncing_bar_params).
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

/// A body's initial displacement u(x, 0), linear in x along the whole body (through its
/// segments): `left` at its first node, `right` at its last, u_j = left·(1 − x_j/L) +
/// right·x_j/L at node j (x_j from the first node, L the body's length). [mm], finite. The default,
/// zero, is an undisplaced body; right ≠ left is an initial strain (right − left)/L in every
/// segment. A node's displacement counts from its reference position, so a wall or a neighbour's
/// gap is to the undisplaced end: the initial state must keep every contact's constraint
/// (validate()), and a clamped end must have zero displacement.
struct LinearDisplacement {
  double left = 0.0;   ///< u at the body's first node [mm]
  double right = 0.0;  ///< u at its last node [mm]

  bool is_zero() const { return left == 0.0 && right == 0.0; }
  bool operator==(const LinearDisplacement&) const = default;
};

/// One rod: segments from left to right, welded together; its nodes are numbered left to right.
struct Body {
  std::string name;                 ///< unique within the scene; letters, digits and '_'
  double velocity = 0.0;            ///< initial velocity of every node [mm/s], +x positive, finite
  double gap = 0.0;                 ///< gap to the body (or the wall) on its left [mm], >= 0
  std::vector<Segment> segments;    ///< at least one
  LinearDisplacement displacement;  ///< initial displacement; default none

  bool operator==(const Body&) const = default;
};

/// What a wall does to the end node next to it.
enum class WallKind {
  /// A rigid obstacle: the unilateral contact of the header comment, at `gap`. The default.
  contact,
  /// The end node held at u = 0 for all time (a Dirichlet condition, exact: the node's DOF is
  /// removed from the assembled system). Not a contact; its gap must be 0 and the node's initial
  /// displacement 0. The body's initial velocity still applies to its other nodes.
  clamped,
};
/// "contact", "clamped": the names of plan and scene files (`kind` of [scene.wall.<side>]).
const char* to_string(WallKind kind);
std::optional<WallKind> wall_kind_from_string(const std::string& name);

struct Wall {
  WallKind kind = WallKind::contact;
  double gap = 0.0;  ///< gap between the wall and the end node next to it [mm], >= 0; a contact's

  bool operator==(const Wall&) const = default;
};

struct Scene {
  std::vector<Body> bodies;  ///< at least one, left to right
  /// Optional rigid walls. The left wall's gap is Wall::gap; body 0's own gap must be 0 (a scene
  /// file's `gap` on its first body is the left wall's gap, and the parser puts it there).
  std::optional<Wall> left_wall, right_wall;
  MassMatrix mass = MassMatrix::lumped;
  /// g: the x-component of a uniform acceleration of every body (gravity) [mm/s²], finite; 0 (the
  /// default) is none. Non-zero, it must point toward a wall: g < 0 toward wall.left, g > 0
  /// toward wall.right (a contact or a clamp), the zero of the potential energy.
  double gravity = 0.0;
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

/// Whether every body starts free and unstrained and nothing but contact acts on it: no clamped
/// wall, no initial displacement, no gravity. Only then does each body fly rigidly (u = v0·t)
/// until its first contact, which the run's filled-in free flight, the exact solution of the
/// chain and the batched chain kernel assume.
bool bodies_start_free(const Scene& scene);

/// Whether the scene is in the paper's form: one body of one segment, starting free
/// (bodies_start_free), and a contact wall on the right, nothing else.
bool in_paper_form(const Scene& scene);

/// The other way: the rod's shorthand of a scene in the paper's form (in_paper_form), with the
/// scene's end time stated, whose run is the scene's bit for bit (the same matrices, step, time
/// grid and free flight: core/model/scene_assembly.hpp). Sweeps run such scenes in the rod's
/// batched kernel. Nothing for any other scene: a clamped end or an initial displacement, which
/// RodScene cannot say, is never taken for the paper's rod.
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
  /// Time at which the gap closes if every body flew rigidly from its initial position (+inf if
  /// it never does) [s]: the gap less the initial displacements' closing of it (Body::
  /// displacement), over the approach velocity; for a wall under gravity, the time of the fall
  /// (or rise) at constant acceleration that closes it.
  double rigid_closing_time;
};
/// The contacts of the scene; a clamped wall is none.
std::vector<SceneContact> scene_contacts(const Scene& scene);

/// First invalid field of the scene, named by its dotted path (`body.striker.segment.1.area`,
/// `wall.left.gap`, `wall.right.kind`, `body.bar.displacement`, `courant`), or nothing.
std::optional<ParameterError> validate(const Scene& scene);

/// Quantities derived from a valid scene, computed in one place.
struct SceneDerived {
  double time_step;           ///< Δt [s]
  double min_h_over_c;        ///< smallest h/c over all segments [s]
  double first_contact_time;  ///< earliest rigid closing time (+inf if no contact closes) [s]
  int primary_contact;        ///< index into scene_contacts()
  double end_time;            ///< t_end [s]
  long step_count;            ///< N = ⌈t_end/Δt − 1e-9⌉; samples t_i = i·Δt, i = 1..N
  /// Σ ½·ρ·A·L·v² + Σ ½·E·A·L·ε² over the segments, ε a body's initial strain, and under gravity
  /// the potential Σ ρ·A·|g|·∫ height [mJ]: the continuum's energy at t = 0, checked by validate()
  /// (a run's own is ½vᵀMv + ½uᵀKu + V₀ − fᵀu of the assembled system).
  double initial_energy;
  /// The largest of a body's |v0|, of c·|ε| over its segments (the particle velocity an
  /// initial strain ε releases) and, under gravity, of the speed a body strikes the wall it falls
  /// toward [mm/s]: the scale of the scene's velocities.
  double velocity_scale;
  long nodes;  ///< Σ (elements + 1) over the bodies, clamped nodes included
};
SceneDerived derive(const Scene& scene);

/// Two-way transit time Σ 2·L_s/c_s of a body [s].
double transit_time(const Body& body);
/// First node index of each body in the assembled system, and one past the last.
std::vector<long> body_first_nodes(const Scene& scene);
/// The reference position x of each body's first node [mm], from the left wall (or, without one,
/// from body 0's first node), and last the right wall's (the last body's end plus its gap; the
/// last body's end without a right wall).
std::vector<double> body_positions(const Scene& scene);
/// The height of the reference position x above the wall gravity points to [mm]: x for g < 0,
/// the right wall's position less x for g > 0 (`positions`: body_positions(scene)).
double height_above_wall(const Scene& scene, const std::vector<double>& positions, double x);

}  // namespace impactid
