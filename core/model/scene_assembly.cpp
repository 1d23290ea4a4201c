#include "core/model/scene_assembly.hpp"

#include <algorithm>

namespace impactid {

namespace {

// The matrix without its first row and column (`first`) and without its last (`last`): the
// clamped nodes' DOFs removed. Their couplings to the remaining DOFs drop out with them, exact
// since the clamped displacement, velocity and acceleration are 0.
Tridiagonal without_ends(const Tridiagonal& a, bool first, bool last) {
  const Eigen::Index begin = first ? 1 : 0;
  const Eigen::Index n = a.size() - begin - (last ? 1 : 0);
  Tridiagonal out{a.lower.segment(begin, n), a.diag.segment(begin, n), a.upper.segment(begin, n)};
  out.lower[0] = 0.0;      // unused, and the coupling to a removed first DOF
  out.upper[n - 1] = 0.0;  // likewise
  return out;
}

// A body's initial displacement at its nodes, u_j = left·(1 − ξ_j) + right·ξ_j with ξ_j = x_j/L
// (core/model/scene.hpp: LinearDisplacement), into `u` (one entry per node of the body). The last
// node gets ξ = 1 exactly, whatever the rounding of the sum of the segments' lengths.
void set_linear_displacement(const Body& body, Eigen::Ref<Eigen::VectorXd> u) {
  double length = 0.0;
  for (const Segment& seg : body.segments) length += seg.length;
  const LinearDisplacement& d = body.displacement;
  Eigen::Index node = 0;
  double start = 0.0;  // x of the segment's first node
  for (const Segment& seg : body.segments) {
    const double h = seg.length / seg.elements;
    for (int e = 0; e < seg.elements; ++e, ++node) {
      const double xi = (start + e * h) / length;
      u[node] = d.left * (1.0 - xi) + d.right * xi;
    }
    start += seg.length;
  }
  u[node] = d.right;
}

// Gravity's load (core/model/constant_load.hpp) on DOFs [first_dof, first_dof + dofs) of the
// nodes: each element's weight ρ·A·h·g halved onto its two nodes, the consistent load of a uniform
// body force on linear elements (whatever the mass matrix), and its potential at rest,
// Σ |f_i|·height_i above the wall gravity points to. A clamped node (outside the range) gives its
// weight to the clamp; it does not move, so its constant potential is left out.
ConstantLoad gravity_load(const Scene& scene, Eigen::Index nodes, Eigen::Index first_dof,
                          Eigen::Index dofs) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(nodes), height(nodes);
  const std::vector<double> x = body_positions(scene);
  const std::vector<long> first = body_first_nodes(scene);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    Eigen::Index node = first[b];
    double start = x[b];
    for (const Segment& seg : scene.bodies[b].segments) {
      const double h = seg.length / seg.elements;
      const double half_weight = 0.5 * seg.density * seg.area * h * scene.gravity;
      for (int e = 0; e < seg.elements; ++e, ++node) {
        force[node] += half_weight;
        force[node + 1] += half_weight;
        height[node] = height_above_wall(scene, x, start + e * h);
      }
      start += seg.length;
    }
    height[node] = height_above_wall(scene, x, start);
  }
  ConstantLoad load;
  load.force = force.segment(first_dof, dofs);
  load.rest_potential = load.force.cwiseAbs().dot(height.segment(first_dof, dofs));
  return load;
}

// A modified mass (MassMatrix::redistributed, singular) at every contact node, as assemble_rod
// does at the rod's walls (apply_contact_mass, core/model/second_order_system.hpp): a wall's end
// node, and both end nodes of a pair of bodies, each with its neighbour in its end element.
void apply_contact_masses(const Scene& scene, const std::vector<long>& first, Tridiagonal& mass) {
  const auto apply = [&](Eigen::Index node, Eigen::Index neighbour, const Segment& seg) {
    const double element_mass = seg.density * seg.area * (seg.length / seg.elements);
    apply_contact_mass(mass, node, neighbour, element_mass, scene.mass);
  };
  for (const SceneContact& c : scene_contacts(scene)) {
    if (c.left_body >= 0) {
      const auto b = static_cast<std::size_t>(c.left_body);
      const Eigen::Index last = first[b + 1] - 1;
      apply(last, last - 1, scene.bodies[b].segments.back());
    }
    if (c.right_body >= 0) {
      const auto b = static_cast<std::size_t>(c.right_body);
      apply(first[b], first[b] + 1, scene.bodies[b].segments.front());
    }
  }
}

}  // namespace

AssembledScene assemble(const Scene& scene) {
  const SceneDerived derived = derive(scene);
  const std::vector<long> first = body_first_nodes(scene);
  const auto nodes = static_cast<Eigen::Index>(first.back());
  // A clamped node is no DOF: node k is DOF k − offset, of `dofs` in all.
  const bool clamp_first = scene.left_wall && scene.left_wall->kind == WallKind::clamped;
  const bool clamp_last = scene.right_wall && scene.right_wall->kind == WallKind::clamped;
  const Eigen::Index offset = clamp_first ? 1 : 0;
  const Eigen::Index dofs = nodes - offset - (clamp_last ? 1 : 0);

  AssembledScene out;
  SecondOrderSystem& sys = out.system;
  sys.mass = Tridiagonal::zero(nodes);
  sys.stiffness = Tridiagonal::zero(nodes);
  Eigen::VectorXd velocity(nodes);
  Eigen::VectorXd displacement;
  const bool displaced = std::any_of(scene.bodies.begin(), scene.bodies.end(),
                                     [](const Body& b) { return !b.displacement.is_zero(); });
  if (displaced) displacement.setZero(nodes);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    Eigen::Index node = first[b];
    for (const Segment& seg : body.segments) {
      add_truss_elements(sys, node, seg.elements, seg.length, seg.youngs_modulus, seg.density,
                         seg.area, scene.mass);
      node += seg.elements;
    }
    velocity.segment(first[b], first[b + 1] - first[b]).setConstant(body.velocity);
    if (displaced) {
      set_linear_displacement(body, displacement.segment(first[b], first[b + 1] - first[b]));
    }
  }
  if (has_massless_dofs(scene.mass)) apply_contact_masses(scene, first, sys.mass);
  if (clamp_first || clamp_last) {
    sys.mass = without_ends(sys.mass, clamp_first, clamp_last);
    sys.stiffness = without_ends(sys.stiffness, clamp_first, clamp_last);
    out.initial_velocity = velocity.segment(offset, dofs);
  } else {
    out.initial_velocity = std::move(velocity);
  }
  if (displaced) out.initial_displacement = displacement.segment(offset, dofs);
  if (scene.gravity != 0.0) sys.load = gravity_load(scene, nodes, offset, dofs);
  sys.damping = sys.mass.combined(scene.rayleigh_mass, sys.stiffness, scene.rayleigh_stiffness);

  const std::vector<SceneContact> contacts = scene_contacts(scene);
  const bool paper_form = in_paper_form(scene);
  for (const SceneContact& c : contacts) {
    Constraint con{.gap = c.gap};
    if (c.left_body >= 0) con.plus = first[static_cast<std::size_t>(c.left_body) + 1] - 1 - offset;
    if (c.right_body >= 0) con.minus = first[static_cast<std::size_t>(c.right_body)] - offset;
    // The reported node: the left body's end node; for the left wall, body 0's first node.
    out.probes.push_back({c.area, c.left_body >= 0 ? con.plus : con.minus});
    if (paper_form) {
      sys.contact_dof = con.plus;
      sys.gap = con.gap;
    } else {
      sys.constraints.push_back(con);
    }
  }
  out.dt = derived.time_step;
  out.step_count = derived.step_count;
  out.first_contact_time = derived.first_contact_time;
  out.starts_free = bodies_start_free(scene);
  out.rigid_flight = scene.rayleigh_mass == 0.0 && out.starts_free;
  out.primary = derived.primary_contact;
  out.mass = scene.mass;
  return out;
}

AssembledScene assemble(const RodScene& rod) {
  const RodSceneDerived derived = derive(rod);
  AssembledScene out;
  out.system = assemble_rod(rod);
  out.initial_velocity.setConstant(out.system.size(), rod.velocity);
  out.dt = derived.time_step;
  out.step_count = derived.step_count;
  out.first_contact_time = derived.impact_time;
  out.rigid_flight = rod.rayleigh_mass == 0.0;
  out.probes = {{rod.area, out.system.contact_dof}};
  out.primary = 0;
  out.contact_columns = false;
  out.mass = rod.mass;
  return out;
}

}  // namespace impactid
