// A scene of bodies (core/model/scene.hpp) turned into what a run needs: the assembled second-order
// system with its constraints, the initial state, the time grid, and where each contact's
// pressure and velocity are read. The run (simulate() of core/run/simulation.hpp) sees only this;
// each kind of scene produces one.
//
// Nodes are numbered body by body, left to right; a body's segments share their junction nodes
// (welded), and bodies are coupled only through the constraints, so every matrix stays
// tridiagonal with zeros between bodies. A clamped wall's node (WallKind::clamped) is no DOF: its
// row and column are removed from M, C and K (u = 0 held exactly, no penalty), so DOF k is node
// k − 1 when the left end is clamped and node k otherwise, and a clamped right end drops the last
// node. A body's initial displacement (Body::displacement) is interpolated at its nodes.
//
// The rod's scene (RodScene) is assembled with the named contacts too, by assemble(RodScene),
// with its own time grid. The paper's form of a Scene (in_paper_form: one body of one segment
// starting free and a contact wall on the right, nothing else) is assembled with the system's
// named contact (SecondOrderSystem::contact_dof, gap), through which the paper's scene has always
// run: the same matrices, the same step, the same bits as simulate(RodScene). Every other scene
// lists its constraints (SecondOrderSystem::constraints), in scene_contacts() order.
//
// Thread safety: values.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/model/scene.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// Where a contact's samples are read: pressure = λ/area, velocity = v[velocity_dof].
struct ContactProbe {
  double area;
  Eigen::Index velocity_dof;
};

struct AssembledScene {
  SecondOrderSystem system;
  /// A user's model whose matrices are not all tridiagonal (core/model/model_scene.hpp): the run's
  /// system, with its constraints; `system` is then unused. Shared, so that copies of a scene
  /// (a sweep's points) hold one model.
  std::shared_ptr<const SparseSystem> sparse;
  Eigen::VectorXd initial_velocity;  ///< per dof [mm/s]
  /// Per dof [mm]; empty: zero (every scene of bodies without Body::displacement). A scene with
  /// one sets rigid_flight false.
  Eigen::VectorXd initial_displacement;
  double dt = 0.0;      ///< [s]
  long step_count = 0;  ///< N; samples t_i = i·Δt, i = 1..N
  /// Before this time every body flies rigidly (no contact has closed) [s]; +inf if none closes.
  double first_contact_time = 0.0;
  /// Whether every body starts free and unstrained (core/model/scene.hpp: bodies_start_free):
  /// false with a clamped end or an initial displacement. The batched chain kernel takes only
  /// scenes that do (core/batch/batched_chain.hpp: chain_batchable).
  bool starts_free = true;
  /// Whether the free flight may be filled in rather than stepped: every body starts free
  /// (starts_free: a clamp or an initial strain makes the flight anything but u = v0·t) and
  /// nothing slows a body in flight (no mass-proportional damping).
  bool rigid_flight = true;
  std::vector<ContactProbe> probes;  ///< one per contact, scene_contacts() order (or the model's)
  int primary = 0;                   ///< index of the primary contact
  /// Whether a run fills ContactTrace::contact_pressure and contact_velocity. The rod's
  /// shorthand does not: its contact is the trace's pressure and velocity, its far wall's
  /// pressure far_pressure, as they always were.
  bool contact_columns = true;
  /// The mass treatment it was assembled with (core/model/rod_scene.hpp); a model's is its file's,
  /// lumped here. With massless DOFs (redistributed, singular) simulate() runs only the methods
  /// that step them (MethodDescriptor::massless_dofs).
  MassMatrix mass = MassMatrix::lumped;
};

/// The scene must be valid (validate()).
AssembledScene assemble(const Scene& scene);

/// The rod's scene, valid: assemble_rod's system (the wall and the far wall as the named
/// contacts), the rod's time grid (RodSceneDerived) and its free flight, which ends at the main
/// wall's impact (a rod flying toward the far wall is stepped from the start). One probe, the
/// main wall's.
AssembledScene assemble(const RodScene& rod);

}  // namespace impactid
