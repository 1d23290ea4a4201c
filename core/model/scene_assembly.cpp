#include "core/model/scene_assembly.hpp"

namespace impactid {

AssembledScene assemble(const Scene& scene) {
  const SceneDerived derived = derive(scene);
  const std::vector<long> first = body_first_nodes(scene);
  const auto nodes = static_cast<Eigen::Index>(first.back());

  AssembledScene out;
  SecondOrderSystem& sys = out.system;
  sys.mass = Tridiagonal::zero(nodes);
  sys.stiffness = Tridiagonal::zero(nodes);
  out.initial_velocity.resize(nodes);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    Eigen::Index node = first[b];
    for (const Segment& seg : body.segments) {
      add_truss_elements(sys, node, seg.elements, seg.length, seg.youngs_modulus, seg.density,
                         seg.area, scene.mass);
      node += seg.elements;
    }
    out.initial_velocity.segment(first[b], first[b + 1] - first[b]).setConstant(body.velocity);
  }
  sys.damping = sys.mass.combined(scene.rayleigh_mass, sys.stiffness, scene.rayleigh_stiffness);

  const std::vector<SceneContact> contacts = scene_contacts(scene);
  const bool paper_form = scene.bodies.size() == 1 && scene.bodies[0].segments.size() == 1 &&
                          !scene.left_wall && scene.right_wall;
  for (const SceneContact& c : contacts) {
    Constraint con{.gap = c.gap};
    if (c.left_body >= 0) con.plus = first[static_cast<std::size_t>(c.left_body) + 1] - 1;
    if (c.right_body >= 0) con.minus = first[static_cast<std::size_t>(c.right_body)];
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
  out.rigid_flight = scene.rayleigh_mass == 0.0;
  out.primary = derived.primary_contact;
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
  return out;
}

}  // namespace impactid
