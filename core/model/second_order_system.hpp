// The semi-discrete equation of motion with one unilateral contact constraint,
//   M·ü + C·u̇ + K·u + G^T·λ = f,  g = u_c − gap <= 0,  λ >= 0,  λ·g = 0
// (eqs 16–17 of the paper), with G = e_c selecting the contact degree of freedom c and f a
// constant load, absent (zero) but for a scene of bodies under gravity or a model with a
// [scene.load] (`load`).
// All three matrices are tridiagonal, so every integrator step is O(n).
//
// An optional second constraint acts on far_contact_dof from the other side:
//   g_0 = −u_0 − far_gap <= 0,  λ_0 >= 0,  λ_0·g_0 = 0,  force +λ_0 on that dof (G_0 = −e_0),
// the far wall of the repeated-impact scene. With far_gap = +inf (the default) it is absent and
// every integrator runs its single-contact code unchanged.
//
// Scenes of several bodies (core/model/scene.hpp) need more constraints than these two: their
// system lists them in `constraints`, each g_k = u[plus] − u[minus] − gap_k <= 0 with force
// −G_kᵀ·λ_k, and leaves gap and far_gap at +inf. The integrators then solve the constraints
// together (core/algebra/contact_lcp.hpp). The two named constraints above are kept as they are
// because the paper's scene runs through them bit for bit as it always has; a system uses one form
// or the other, never both.
//
// The rod scene assembles one (assemble_rod), a scene of bodies another (assemble in
// core/model/scene_assembly.hpp); tests build others (free vibration without a wall, other boundary
// conditions) directly.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/model/constant_load.hpp"
#include "core/model/rod_scene.hpp"

namespace impactid {

/// One unilateral constraint of the general form: u[plus] − u[minus] − gap <= 0, where a dof
/// index of −1 means the term is absent (a wall on the right: minus = −1; on the left: plus = −1).
struct Constraint {
  Eigen::Index plus = -1;
  Eigen::Index minus = -1;
  double gap = 0.0;  ///< [mm], >= 0
};

struct SecondOrderSystem {
  /// The matrices' type and the factorisation of the steppers' matrices (core/model/
  /// semi_discrete_system.hpp).
  using Matrix = Tridiagonal;
  using Factorization = TridiagonalFactorization;

  Tridiagonal mass;
  Tridiagonal damping;  ///< all zero when there is no damping; integrators then skip C terms
  Tridiagonal stiffness;
  Eigen::Index contact_dof = 0;
  /// Allowed displacement of the contact dof toward the wall; +inf means no wall.
  double gap = std::numeric_limits<double>::infinity();
  Eigen::Index far_contact_dof = 0;
  /// Allowed displacement of far_contact_dof away from the wall (u >= −far_gap); +inf: no wall.
  double far_gap = std::numeric_limits<double>::infinity();

  /// The general constraints (see above); empty for the named-constraint form.
  std::vector<Constraint> constraints;
  /// A constant external force f on the right-hand side (core/model/constant_load.hpp: gravity on
  /// a scene of bodies, a model's [scene.load]); empty for the rod and every scene without one.
  ConstantLoad load;

  Eigen::Index size() const { return mass.size(); }
  bool has_constraint_list() const { return !constraints.empty(); }
  bool has_contact() const { return gap < std::numeric_limits<double>::infinity(); }
  bool has_far_contact() const { return far_gap < std::numeric_limits<double>::infinity(); }
  bool has_damping() const { return !damping.is_zero(); }
  /// ½·v^T·M·v + ½·u^T·K·u, and the load's potential V₀ − fᵀ·u when there is one
  double energy(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
    const double e = 0.5 * mass.quadratic_form(v) + 0.5 * stiffness.quadratic_form(u);
    return load.active() ? e + load.potential(u) : e;
  }
};

/// Adds `elements` 2-node truss elements of length/elements each (E, ρ, A) to the system's mass
/// and stiffness, from node `first_node` on: the rod's assembly, and each segment's in a scene of
/// bodies (core/model/scene_assembly.hpp).
void add_truss_elements(SecondOrderSystem& system, Eigen::Index first_node, int elements,
                        double length, double youngs_modulus, double density, double area,
                        MassMatrix mass);

/// A modified mass (MassMatrix::redistributed or singular, core/model/rod_scene.hpp) at one
/// contact node: `mass` assembled with its base (lumped or consistent), the contact node and its
/// neighbour in the same element of mass ρAh = element_mass. The contact node's row and column
/// become zero. Nothing for lumped or consistent.
void apply_contact_mass(Tridiagonal& mass, Eigen::Index contact, Eigen::Index neighbour,
                        double element_mass, MassMatrix kind);

/// Whether DOF i has no mass: its row of M is zero (the contact DOFs of a modified mass).
bool massless(const Tridiagonal& mass, Eigen::Index i);

/// The rod of the scene: n elements, n+1 nodes, contact at node n, Rayleigh damping
/// C = a0·M + a1·K, and the far wall at node 0 when the scene has one. The scene must be valid.
SecondOrderSystem assemble_rod(const RodScene& scene);

}  // namespace impactid
