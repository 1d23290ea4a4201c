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
    // The modified masses start from one of the two (apply_contact_mass then changes the
    // contact elements).
    if (mass == MassMatrix::lumped || mass == MassMatrix::redistributed) {
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

void apply_contact_mass(Tridiagonal& mass, Eigen::Index contact, Eigen::Index neighbour,
                        double element_mass, MassMatrix kind) {
  // Entry (i, j) of the tridiagonal matrix: diag[i] if i = j, upper[i] if j = i + 1, lower[i] if
  // j = i − 1.
  const auto coupling = [&](Eigen::Index i, Eigen::Index j) -> double& {
    return j > i ? mass.upper[i] : mass.lower[i];
  };
  if (kind == MassMatrix::redistributed) {
    // Lumped: the contact node's mass, ρAh/2, moves whole onto its neighbour; nothing couples them.
    mass.diag[neighbour] += mass.diag[contact];
  } else if (kind == MassMatrix::singular) {
    // Consistent: the contact element gave the neighbour ρAh/3; its midpoint rule with the
    // contact node's velocity left out gives ρAh/4 (core/model/rod_scene.hpp), so 7ρAh/12 in all.
    mass.diag[neighbour] -= element_mass / 12.0;
    coupling(contact, neighbour) = 0.0;
    coupling(neighbour, contact) = 0.0;
  } else {
    return;
  }
  mass.diag[contact] = 0.0;
}

bool massless(const Tridiagonal& mass, Eigen::Index i) {
  const Eigen::Index n = mass.size();
  return mass.diag[i] == 0.0 && (i == 0 || mass.lower[i] == 0.0) &&
         (i + 1 == n || mass.upper[i] == 0.0);
}

SecondOrderSystem assemble_rod(const RodScene& scene) {
  const Eigen::Index nodes = scene.elements + 1;
  SecondOrderSystem system;
  system.mass = Tridiagonal::zero(nodes);
  system.stiffness = Tridiagonal::zero(nodes);
  add_truss_elements(system, 0, scene.elements, scene.length, scene.youngs_modulus, scene.density,
                     scene.area, scene.mass);
  if (has_massless_dofs(scene.mass)) {
    const double element_mass = scene.density * scene.area * (scene.length / scene.elements);
    apply_contact_mass(system.mass, nodes - 1, nodes - 2, element_mass, scene.mass);
    if (scene.far_gap) apply_contact_mass(system.mass, 0, 1, element_mass, scene.mass);
  }
  system.damping =
      system.mass.combined(scene.rayleigh_mass, system.stiffness, scene.rayleigh_stiffness);
  system.contact_dof = nodes - 1;
  system.gap = scene.gap;
  if (scene.far_gap) system.far_gap = *scene.far_gap;  // far_contact_dof = 0
  return system;
}

}  // namespace impactid
