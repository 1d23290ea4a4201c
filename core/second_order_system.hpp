// The semi-discrete equation of motion with one unilateral contact constraint,
//   M·ü + C·u̇ + K·u + G^T·λ = 0,  g = u_c − gap <= 0,  λ >= 0,  λ·g = 0
// (eqs 16–17 of the paper), with G = e_c selecting the contact degree of freedom c.
// All three matrices are tridiagonal, so every integrator step is O(n).
//
// The rod scene assembles one (assemble_rod); tests build others (free vibration without a
// wall, other boundary conditions) directly.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "core/rod_scene.hpp"
#include "core/tridiagonal.hpp"

namespace impactid {

struct SecondOrderSystem {
  Tridiagonal mass;
  Tridiagonal damping;  ///< all zero when there is no damping; integrators then skip C terms
  Tridiagonal stiffness;
  Eigen::Index contact_dof = 0;
  /// Allowed displacement of the contact dof toward the wall; +inf means no wall.
  double gap = std::numeric_limits<double>::infinity();

  Eigen::Index size() const { return mass.size(); }
  bool has_contact() const { return gap < std::numeric_limits<double>::infinity(); }
  bool has_damping() const { return !damping.is_zero(); }
  /// ½·v^T·M·v + ½·u^T·K·u
  double energy(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
    return 0.5 * mass.quadratic_form(v) + 0.5 * stiffness.quadratic_form(u);
  }
};

/// The rod of the scene: n elements, n+1 nodes, contact at node n, Rayleigh damping
/// C = a0·M + a1·K. The scene must be valid.
SecondOrderSystem assemble_rod(const RodScene& scene);

}  // namespace impactid
