#include "core/methods/central_difference.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/two_wall_contact.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/stable_step.hpp"

namespace impactid {

bool CentralDifference::initialize(const SecondOrderSystem& system, CdmVelocity velocity, double dt,
                                   const State& initial, const ContactPenalties& contact) {
  contact_ = contact;
  const double bound = highest_frequency_squared_bound(system, contact);
  within_limit_ = within_explicit_limit(dt, bound);
  stable_step_ = std::isfinite(bound) ? 2.0 / std::sqrt(bound) : 0.0;
  const double damping_weight =
      (velocity == CdmVelocity::central && system.has_damping()) ? 0.5 / dt : 0.0;
  const Tridiagonal lhs = system.mass.combined(1.0 / (dt * dt), system.damping, damping_weight);
  if (!factorization_.factor(lhs)) return false;

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
  return true;
}

bool CentralDifference::step(const SecondOrderSystem& system, State& at_t) {
  recurrence_.predict(system, factorization_);
  Eigen::VectorXd& u_next = recurrence_.u_next;
  const Eigen::VectorXd& u = recurrence_.u;

  double lambda = 0.0;
  const Eigen::Index contact = system.contact_dof;
  if (system.has_constraint_list()) {
    const auto m = static_cast<int>(system.constraints.size());
    // The penalty's violations are those at t (its force is explicit); the others' at t + Δt.
    list_law_.forward_increment(system.constraints, list_, u_next, u, forces_);
    apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, u_next);
    if (contact_.lagrange()) snap_walls(system.constraints, forces_, u_next);
    at_t.multipliers = forces_;  // the same size: no allocation
    for (int j = 0; j < m; ++j) lambda = std::max(lambda, forces_[j]);
  } else if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    TwoWallForces forces;
    if (contact_.lagrange()) {
      forces = solve_two_wall_contact(u_next[contact] - system.gap, -system.far_gap - u_next[far],
                                      contact_influence_[contact], far_influence_[far],
                                      far_influence_[contact], contact_influence_[far]);
    } else if (contact_.law == ContactLaw::penalty) {
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
      if (forces.main > 0.0) u_next[contact] = system.gap;
      if (forces.far > 0.0) u_next[far] = -system.far_gap;
    }
    lambda = forces.main;
    at_t.far_lambda = forces.far;
  } else if (contact_.law == ContactLaw::penalty) {
    if (system.has_contact() && u[contact] > system.gap) {
      lambda = contact_.main * (u[contact] - system.gap);
      u_next -= lambda * contact_influence_;
    }
  } else if (system.has_contact() && u_next[contact] > system.gap) {
    if (contact_.lagrange()) {
      lambda = (u_next[contact] - system.gap) / contact_influence_[contact];
      u_next -= lambda * contact_influence_;
      u_next[contact] = system.gap;  // exact, not a few ulps off
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
