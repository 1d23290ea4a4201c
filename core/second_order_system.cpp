#include "core/second_order_system.hpp"

namespace impactid {

SecondOrderSystem assemble_rod(const RodScene& scene) {
  const Eigen::Index nodes = scene.elements + 1;
  const double h = scene.length / scene.elements;
  const double element_mass = scene.density * scene.area * h;
  const double element_stiffness = scene.youngs_modulus * scene.area / h;

  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(nodes);
  system.stiffness = Tridiagonal::zero(nodes);
  for (Eigen::Index e = 0; e < scene.elements; ++e) {
    const Eigen::Index i = e, j = e + 1;
    system.stiffness.diag[i] += element_stiffness;
    system.stiffness.diag[j] += element_stiffness;
    system.stiffness.upper[i] -= element_stiffness;
    system.stiffness.lower[j] -= element_stiffness;
    if (scene.mass == MassMatrix::lumped) {
      system.mass.diag[i] += 0.5 * element_mass;
      system.mass.diag[j] += 0.5 * element_mass;
    } else {
      system.mass.diag[i] += element_mass / 3.0;
      system.mass.diag[j] += element_mass / 3.0;
      system.mass.upper[i] += element_mass / 6.0;
      system.mass.lower[j] += element_mass / 6.0;
    }
  }
  system.damping =
      system.mass.combined(scene.rayleigh_mass, system.stiffness, scene.rayleigh_stiffness);
  system.contact_dof = nodes - 1;
  system.gap = scene.gap;
  if (scene.far_gap) system.far_gap = *scene.far_gap;  // far_contact_dof = 0
  return system;
}

}  // namespace impactid
