#include "core/methods/central_difference.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/two_wall_contact.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/paoli_schatzman_law.hpp"
#include "core/contact/stable_step.hpp"

namespace impactid {

bool CentralDifference::initialize(const SecondOrderSystem& system, CdmVelocity velocity, double dt,
                                   const State& initial, const ContactPenalties& contact) {
  contact_ = contact;
  failure_.clear();
  const double bound = highest_frequency_squared_bound(system, contact);
  within_limit_ = within_explicit_limit(dt, bound);
  stable_step_ = std::isfinite(bound) ? 2.0 / std::sqrt(bound) : 0.0;
  const double damping_weight =
      (velocity == CdmVelocity::central && system.has_damping()) ? 0.5 / dt : 0.0;
  Tridiagonal lhs = system.mass.combined(1.0 / (dt * dt), system.damping, damping_weight);
  massless_main_ = system.has_contact() && massless(system.mass, system.contact_dof);
  massless_far_ = system.has_far_contact() && massless(system.mass, system.far_contact_dof);
  // A scene of bodies' massless contact nodes (a constraint list) are none of the named walls':
  // massless_failure() names what refuses them.
  bool listed_massless = false;
  for (Eigen::Index i = 0; system.has_constraint_list() && i < system.size(); ++i) {
    listed_massless = listed_massless || massless(system.mass, i);
  }
  if (listed_massless) {
    failure_ = massless_failure(system);
    return false;
  }
  if (massless_main_ || massless_far_) {
    failure_ = massless_failure(system);
    if (failure_.empty() && contact_.restitution > 0.0) {
      failure_ =
          "paoli-schatzman's restitution is not defined on a massless contact DOF (its "
          "static equation has no previous displacement): restitution = 0, or mass = "
          "lumped|consistent";
    }
    if (!failure_.empty()) return false;
    // A unit row: the recurrence's value there is overwritten by the static solve.
    if (massless_main_) lhs.diag[system.contact_dof] = 1.0;
    if (massless_far_) lhs.diag[system.far_contact_dof] = 1.0;
    next_lambda_ = initial.lambda;
    next_far_lambda_ = initial.far_lambda;
  }
  if (!factorization_.factor(lhs)) {
    failure_ = "singular left-hand matrix";
    return false;
  }

  contact_influence_ = factorization_.inverse_column(system.contact_dof);
  if (system.has_far_contact()) {
    far_influence_ = factorization_.inverse_column(system.far_contact_dof);
  } else {
    far_influence_.resize(0);
  }
  recurrence_.start(velocity, dt, initial);
  Eigen::MatrixXd delassus;
  set_up_constraints(system, factorization_, 1.0, constraint_influence_, constraint_rows_,
                     delassus);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::explicit_spring);
  list_ = list_law_.problem(std::move(delassus));
  forces_.resize(m);
  gap_shifts_.setZero(m);
  return true;
}

std::string CentralDifference::massless_failure(const SecondOrderSystem& system) {
  const Eigen::Index n = system.size();
  if (system.has_constraint_list()) {
    return "a massless contact node of a scene of bodies is not supported yet (its constraints "
           "are a list): choose an implicit method, or mass = lumped|consistent";
  }
  if (system.load.active()) {
    return "a massless DOF under a load is not supported (its static equation leaves the load out)";
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!massless(system.mass, i)) continue;
    const bool wall = (system.has_contact() && i == system.contact_dof) ||
                      (system.has_far_contact() && i == system.far_contact_dof);
    if (!wall) return "DOF " + std::to_string(i) + " is massless but carries no contact";
    const Tridiagonal& c = system.damping;
    if (c.diag[i] != 0.0 || (i > 0 && c.lower[i] != 0.0) || (i + 1 < n && c.upper[i] != 0.0)) {
      return "stiffness-proportional damping (rayleigh_stiffness > 0) on the massless contact "
             "DOF " +
             std::to_string(i) + " is not supported: its static equation would need its velocity";
    }
    if (!(system.stiffness.diag[i] > 0.0)) {
      return "the massless DOF " + std::to_string(i) + " has no stiffness";
    }
  }
  if (system.has_far_contact() && system.has_contact() &&
      massless(system.mass, system.contact_dof) != massless(system.mass, system.far_contact_dof)) {
    return "one wall's contact DOF is massless and the other's is not";
  }
  // The two static equations must not couple: node 0 and the contact node are not neighbours.
  if (system.has_far_contact() && std::abs(system.contact_dof - system.far_contact_dof) < 2) {
    return "the two massless contact DOFs are neighbours";
  }
  return "";
}

bool CentralDifference::step_massless(const SecondOrderSystem& system, State& at_t) {
  recurrence_.predict(system, factorization_);
  Eigen::VectorXd& u_next = recurrence_.u_next;
  const Tridiagonal& k = system.stiffness;
  const Eigen::Index n = system.size();
  // The static position of DOF i at t + Δt from its neighbours' (its row of K without its own
  // term), put back onto its wall (side +1: u <= gap; −1: −u <= gap) by the law's force.
  const auto solve_static = [&](Eigen::Index i, double side, double gap, double spring) {
    double coupled = 0.0;
    if (i > 0) coupled += k.lower[i] * u_next[i - 1];
    if (i + 1 < n) coupled += k.upper[i] * u_next[i + 1];
    const double free = -coupled / k.diag[i];
    const double p = side * free - gap;
    double force = 0.0;
    if (p > 0.0) {
      ContactIterations iterations;
      force = massless_contact_force(p, k.diag[i], spring, contact_, iterations);
      list_law_.count(iterations);
    }
    u_next[i] = free - side * force / k.diag[i];
    if (force > 0.0 && contact_.lagrange()) u_next[i] = side * gap;  // exact on the wall
    return force;
  };
  const double lambda = next_lambda_, far_lambda = next_far_lambda_;
  if (massless_main_)
    next_lambda_ = solve_static(system.contact_dof, 1.0, system.gap, contact_.main);
  if (massless_far_) {
    next_far_lambda_ = solve_static(system.far_contact_dof, -1.0, system.far_gap, contact_.far);
  }
  at_t.lambda = lambda;
  if (system.has_far_contact()) at_t.far_lambda = far_lambda;
  recurrence_.finish(at_t);
  return lambda > 0.0;
}

double CentralDifference::shifted_gap(double gap, double previous_violation) const {
  if (!(contact_.restitution > 0.0)) return gap;  // every other law's gap, the same bits
  return gap + restitution_gap_shift(contact_.restitution, previous_violation);
}

bool CentralDifference::step(const SecondOrderSystem& system, State& at_t) {
  if (massless_main_ || massless_far_) return step_massless(system, at_t);
  recurrence_.predict(system, factorization_);
  Eigen::VectorXd& u_next = recurrence_.u_next;
  const Eigen::VectorXd& u = recurrence_.u;

  double lambda = 0.0;
  const Eigen::Index contact = system.contact_dof;
  if (system.has_constraint_list()) {
    const auto m = static_cast<int>(system.constraints.size());
    if (contact_.restitution > 0.0) {  // Paoli–Schatzman: Lagrange's on the shifted gaps
      restitution_gap_shifts(system.constraints, recurrence_.u_previous, contact_.restitution,
                             gap_shifts_);
      constraint_violations(system.constraints, u_next, list_law_.violation());
      list_law_.violation() -= gap_shifts_;
      list_law_.solve(list_, forces_);
    } else {
      // The penalty's violations are those at t (its force is explicit); the others' at t + Δt.
      list_law_.forward_increment(system.constraints, list_, u_next, u, forces_);
    }
    apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, u_next);
    if (contact_.restitution > 0.0) {
      snap_walls(system.constraints, forces_, u_next, gap_shifts_);
    } else if (contact_.lagrange()) {
      snap_walls(system.constraints, forces_, u_next);
    }
    at_t.multipliers = forces_;  // the same size: no allocation
    for (int j = 0; j < m; ++j) lambda = std::max(lambda, forces_[j]);
  } else if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    const Eigen::VectorXd& u_previous = recurrence_.u_previous;
    const double gap = shifted_gap(system.gap, u_previous[contact] - system.gap);
    const double far_gap = shifted_gap(system.far_gap, -system.far_gap - u_previous[far]);
    TwoWallForces forces;
    if (contact_.lagrange()) {
      forces = solve_two_wall_contact(u_next[contact] - gap, -far_gap - u_next[far],
                                      contact_influence_[contact], far_influence_[far],
                                      far_influence_[contact], contact_influence_[far]);
    } else if (contact_.explicit_force()) {
      forces = {contact_.main * std::max(0.0, u[contact] - system.gap),
                contact_.far * std::max(0.0, -system.far_gap - u[far])};
    } else {
      ContactIterations iterations;
      forces = two_wall_contact_forces(
          u_next[contact] - system.gap, -system.far_gap - u_next[far],
          contact_influence_[contact], far_influence_[far], far_influence_[contact],
          contact_influence_[far], 1.0 / contact_.main, 1.0 / contact_.far, contact_, iterations);
      list_law_.count(iterations);
    }
    if (forces.main > 0.0) u_next -= forces.main * contact_influence_;
    if (forces.far > 0.0) u_next += forces.far * far_influence_;
    if (contact_.lagrange()) {
      if (forces.main > 0.0) u_next[contact] = gap;
      if (forces.far > 0.0) u_next[far] = -far_gap;
    }
    lambda = forces.main;
    at_t.far_lambda = forces.far;
  } else if (contact_.explicit_force()) {
    if (system.has_contact() && u[contact] > system.gap) {
      lambda = contact_.main * (u[contact] - system.gap);
      u_next -= lambda * contact_influence_;
    }
  } else if (system.has_contact() &&
             u_next[contact] >
                 shifted_gap(system.gap, recurrence_.u_previous[contact] - system.gap)) {
    if (contact_.lagrange()) {
      const double gap = shifted_gap(system.gap, recurrence_.u_previous[contact] - system.gap);
      lambda = (u_next[contact] - gap) / contact_influence_[contact];
      u_next -= lambda * contact_influence_;
      u_next[contact] = gap;  // exact, not a few ulps off
    } else {
      ContactIterations iterations;
      lambda = single_contact_force(u_next[contact] - system.gap, contact_influence_[contact],
                                    1.0 / contact_.main, contact_, iterations);
      list_law_.count(iterations);
      u_next -= lambda * contact_influence_;
    }
  }

  at_t.lambda = system.has_constraint_list() ? 0.0 : lambda;  // the list's are in multipliers
  recurrence_.finish(at_t);
  return lambda > 0.0;
}

double CentralDifference::energy(const SecondOrderSystem& system, const State& at_t) {
  if (!within_limit_) return system.energy(at_t.u, at_t.v);
  return recurrence_.energy(system);
}

double central_difference_energy(double mass_w, double stiffness_w, double stiffness_m, double dt) {
  return std::abs(0.5 * (mass_w - 0.25 * dt * dt * stiffness_w)) + 0.5 * stiffness_m;
}

}  // namespace impactid
