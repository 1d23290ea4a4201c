// A constant external force on a system's DOFs, the f of
//   M·ü + C·u̇ + K·u + Gᵀ·λ = f,
// and its potential energy. Gravity on a scene of bodies assembles one (core/model/
// scene_assembly.hpp: a uniform body force ρ·g per unit volume, consistent with linear elements:
// ρ·A·h·g/2 at each node of an element, whatever the mass matrix); a system without a load keeps
// it empty, and every stepper then forms its right-hand side exactly as it did before loads
// existed (no term, not a zero term), so that no run without one changes a bit.
//
// The potential energy of a constant force is V(u) = V₀ − fᵀ·u: the work it would do from u
// back to the reference configuration, plus V₀, its value there. The steppers' energies add it
// (core/model/second_order_system.hpp, sparse_system.hpp: energy(); central difference's and
// KR-α's own half-step energies at their midpoint), so the energy a run conserves, and the
// energy bound of core/run/simulation.hpp checks, is kinetic + strain + potential. V₀ sets its
// zero: for gravity, the height above the wall the bodies fall toward, so that a body dropped
// from rest starts with the positive energy m·g·height (as Doyen, Ern & Piperno count the
// bouncing bar's, core/reference/bouncing_bar_exact.hpp).
//
// Thread safety: a value.
#pragma once

#include <Eigen/Core>

namespace impactid {

struct ConstantLoad {
  Eigen::VectorXd force;        ///< f per DOF [N]; empty: no load
  double rest_potential = 0.0;  ///< V₀, the potential energy at u = 0 [mJ]

  bool active() const { return force.size() > 0; }
  /// V(u) = V₀ − fᵀ·u [mJ]; only for an active load.
  double potential(const Eigen::VectorXd& u) const { return rest_potential - force.dot(u); }
};

}  // namespace impactid
