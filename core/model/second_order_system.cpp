#include "core/model/second_order_system.hpp"

namespace impactid {

void add_truss_elements(SecondOrderSystem& system, Eigen::Index first_node, int elements,
                        double length, double youngs_modulus, double density, double area,
                        MassMatrix mass) {
  const double h = length / elements;
  const double element_mass = density * area * h;
  const double element_stiffness = youngs_modulus * area / h;
  for (Eigen::Index e = 0; e < elements; ++e) {
    const Eigen::Index i = first_node + e, j = first_node + e + 1;
    system.stiffness.diag[i] += element_stiffness;
    system.stiffness.diag[j] += element_stiffness;
    system.stiffness.upper[i] -= element_stiffness;
    system.stiffness.lower[j] -= element_stiffness;
    if (mass == MassMatrix::lumped) {
      system.mass.diag[i] += 0.5 * element_mass;
      system.mass.diag[j] += 0.5 * element_mass;
    } else {
      system.mass.diag[i] += element_mass / 3.0;
      system.mass.diag[j] += element_mass / 3.0;
      system.mass.upper[i] += element_mass / 6.0;
      system.mass.lower[j] += element_mass / 6.0;
    }
  }
}

SecondOrderSystem assemble_rod(const RodScene& scene) {
  const Eigen::Index nodes = scene.elements + 1;
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(nodes);
  system.stiffness = Tridiagonal::zero(nodes);
  add_truss_elements(system, 0, scene.elements, scene.length, scene.youngs_modulus, scene.density,
                     scene.area, scene.mass);
  system.damping =
      system.mass.combined(scene.rayleigh_mass, system.stiffness, scene.rayleigh_stiffness);
  system.contact_dof = nodes - 1;
  system.gap = scene.gap;
  if (scene.far_gap) system.far_gap = *scene.far_gap;  // far_contact_dof = 0
  return system;
}

}  // namespace impactid
