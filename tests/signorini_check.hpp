// The Signorini conditions of a state, checked by the tests of the steppers with their own
// arithmetic: for every constraint of the system (the named wall and far wall, or the list; a
// sparse model's list) the violation g = G·u − gap, the multiplier λ, and whether λ > 0 comes
// with g = 0. Nothing here calls the code under test.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "core/common/run_record.hpp"
#include "core/common/state.hpp"
#include "core/methods/implicit_integrator.hpp"  // consistent_acceleration
#include "core/model/rod_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid::testing {

/// Worst values over every constraint of every state recorded.
struct SignoriniRecord {
  double max_violation = -std::numeric_limits<double>::infinity();  ///< max g (> 0: penetration)
  double min_multiplier = std::numeric_limits<double>::infinity();  ///< min λ
  double max_gap_while_pushing = 0.0;  ///< max |g| where λ > 0 (complementarity)
  long pushing = 0;                    ///< (constraint, state) pairs with λ > 0
  long states = 0;

  void record(double g, double lambda) {
    max_violation = std::max(max_violation, g);
    min_multiplier = std::min(min_multiplier, lambda);
    if (lambda > 0.0) {
      max_gap_while_pushing = std::max(max_gap_while_pushing, std::abs(g));
      ++pushing;
    }
  }
};

inline double violation(const Constraint& c, const Eigen::VectorXd& u) {
  double g = -c.gap;
  if (c.plus >= 0) g += u[c.plus];
  if (c.minus >= 0) g -= u[c.minus];
  return g;
}

/// Adds every constraint of `system` at `state` to the record.
template <class System>
void record_signorini(const System& system, const State& state, SignoriniRecord& record) {
  ++record.states;
  for (std::size_t k = 0; k < system.constraints.size(); ++k) {
    record.record(violation(system.constraints[k], state.u),
                  state.multipliers[static_cast<Eigen::Index>(k)]);
  }
  if constexpr (std::is_same_v<System, SecondOrderSystem>) {
    if (system.has_contact()) {
      record.record(state.u[system.contact_dof] - system.gap, state.lambda);
    }
    if (system.has_far_contact()) {
      record.record(-state.u[system.far_contact_dof] - system.far_gap, state.far_lambda);
    }
  }
}

/// The paper's rod with 100 elements, a consistent mass and stiffness damping, its wall as a
/// constraint list, both as a tridiagonal and as a sparse system, and its start (v0 everywhere,
/// the consistent acceleration): the same model on both kinds of integrator.
struct SparseRodPair {
  RodScene rod;
  SecondOrderSystem tridiagonal;
  SparseSystem sparse;
  State start;
};

inline SparseRodPair sparse_rod_pair() {
  SparseRodPair out;
  out.rod.elements = 100;
  out.rod.mass = MassMatrix::consistent;
  out.rod.rayleigh_stiffness = 1e-8;
  out.tridiagonal = assemble_rod(out.rod);
  const Eigen::Index n = out.tridiagonal.size();
  out.tridiagonal.constraints = {{n - 1, -1, out.rod.gap}};
  out.tridiagonal.gap = std::numeric_limits<double>::infinity();
  out.sparse.mass = to_sparse(out.tridiagonal.mass);
  out.sparse.stiffness = to_sparse(out.tridiagonal.stiffness);
  out.sparse.damping = to_sparse(out.tridiagonal.damping);
  out.sparse.constraints = out.tridiagonal.constraints;
  out.start.u = Eigen::VectorXd::Zero(n);
  out.start.v = Eigen::VectorXd::Constant(n, out.rod.velocity);
  out.start.multipliers = Eigen::VectorXd::Zero(1);
  out.start.a = consistent_acceleration(out.tridiagonal, out.start);
  return out;
}

/// Every contact of a run's trace pushed at some sample and never pulled.
inline bool every_contact_pushes_and_never_pulls(const ContactTrace& trace) {
  for (const auto& contact : trace.contact_pressure) {
    if (!(*std::max_element(contact.begin(), contact.end()) > 0.0)) return false;
    if (*std::min_element(contact.begin(), contact.end()) < 0.0) return false;
  }
  return true;
}

/// A scene's start: at rest in place, its initial velocities, `constraints` zero multipliers.
inline State initial_state(const AssembledScene& scene, Eigen::Index constraints) {
  State s;
  s.u = Eigen::VectorXd::Zero(scene.initial_velocity.size());
  s.v = scene.initial_velocity;
  s.a = Eigen::VectorXd::Zero(scene.initial_velocity.size());
  s.multipliers = Eigen::VectorXd::Zero(constraints);
  return s;
}

/// The Signorini conditions to round-off of `scale` (the gap), with at least `min_pushing`
/// pushing (constraint, state) pairs, so that the check cannot pass on a run without contact.
inline void expect_signorini(const SignoriniRecord& r, double scale, long min_pushing) {
  EXPECT_GE(r.min_multiplier, 0.0);
  EXPECT_LE(r.max_violation, 1e-12 * scale);
  EXPECT_LE(r.max_gap_while_pushing, 1e-12 * scale);
  EXPECT_GT(r.pushing, min_pushing);
}

}  // namespace impactid::testing
