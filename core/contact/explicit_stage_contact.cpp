#include "core/contact/explicit_stage_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/two_wall_contact.hpp"
#include "core/contact/constraint_set.hpp"
#include "core/contact/stable_step.hpp"

namespace impactid {

StageStableStep stage_stable_step(double bound, double critical_omega, double dt) {
  if (!std::isfinite(bound)) return {};
  return {bound > 0.0 ? critical_omega / std::sqrt(bound) : std::numeric_limits<double>::infinity(),
          dt * dt * bound <= critical_omega * critical_omega * (1.0 + 1e-12)};
}

bool ExplicitStageContact::initialize(const SecondOrderSystem& system,
                                      const ContactPenalties& contact, double critical_omega,
                                      double dt) {
  contact_ = contact;
  main_ = far_ = 0.0;
  // Ω_crit over the Gershgorin bound on ω_max, with the penalty's springs.
  const StageStableStep stable =
      stage_stable_step(highest_frequency_squared_bound(system, contact), critical_omega, dt);
  stable_step_ = stable.step;
  within_limit_ = stable.within;

  if (!mass_.factor(system.mass)) return false;
  contact_influence_ = mass_.inverse_column(system.contact_dof);
  if (system.has_far_contact()) {
    far_influence_ = mass_.inverse_column(system.far_contact_dof);
  } else {
    far_influence_.resize(0);
  }
  set_up_constraints(system, mass_, 1.0, constraint_influence_, constraint_rows_, delassus_);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  list_law_.initialize(contact_, m, PenaltyForm::explicit_spring);
  forces_.setZero(m);
  scaled_forces_.resize(m);
  return true;
}

StageProblem ExplicitStageContact::problem(double scale) const {
  return {scale, list_law_.problem(scale * delassus_)};
}

void ExplicitStageContact::solve_acceleration(const SecondOrderSystem& system,
                                              const Eigen::VectorXd& u,
                                              const Eigen::VectorXd& v_predicted,
                                              Eigen::VectorXd& a) const {
  if (system.load.active()) {
    a = system.load.force;  // the same size: no allocation
  } else {
    a.setZero();
  }
  system.stiffness.multiply_add(-1.0, u, a);
  if (system.has_damping()) system.damping.multiply_add(-1.0, v_predicted, a);
  mass_.solve_in_place(a);
}

bool ExplicitStageContact::enforce(const SecondOrderSystem& system, const StageProblem& problem,
                                   Eigen::VectorXd& a, Eigen::VectorXd& next,
                                   const Eigen::VectorXd& at_u) {
  const double scale = problem.scale;
  const bool penalty = contact_.law == ContactLaw::penalty;
  main_ = 0.0;
  far_ = 0.0;
  if (system.has_constraint_list()) {
    if (!list_law_.forward_increment(system.constraints, problem.list, next, at_u, forces_)) {
      return false;
    }
    apply_constraint_forces(constraint_influence_, constraint_rows_, forces_, a);
    apply_last(system, scale, next);
    if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
    return true;
  }
  const Eigen::Index contact = system.contact_dof;
  if (system.has_far_contact()) {
    const Eigen::Index far = system.far_contact_dof;
    TwoWallForces forces;
    if (contact_.lagrange()) {
      forces =
          solve_two_wall_contact(next[contact] - system.gap, -system.far_gap - next[far],
                                 scale * contact_influence_[contact], scale * far_influence_[far],
                                 scale * far_influence_[contact], scale * contact_influence_[far]);
    } else if (penalty) {
      forces = {contact_.main * std::max(0.0, at_u[contact] - system.gap),
                contact_.far * std::max(0.0, -system.far_gap - at_u[far])};
    } else {
      ContactIterations iterations;
      forces =
          two_wall_contact_forces(next[contact] - system.gap, -system.far_gap - next[far],
                                  scale * contact_influence_[contact], scale * far_influence_[far],
                                  scale * far_influence_[contact], scale * contact_influence_[far],
                                  1.0 / contact_.main, 1.0 / contact_.far, contact_, iterations);
      list_law_.count(iterations);
    }
    main_ = forces.main;
    far_ = forces.far;
    if (!(main_ > 0.0 || far_ > 0.0)) return false;
    apply_last(system, 1.0, a);
    apply_last(system, scale, next);
    if (contact_.lagrange()) {
      if (main_ > 0.0) next[contact] = system.gap;  // exact, not a few ulps off
      if (far_ > 0.0) next[far] = -system.far_gap;
    }
    return true;
  }
  if (!system.has_contact()) return false;
  if (penalty) {
    if (!(at_u[contact] > system.gap)) return false;
    main_ = contact_.main * (at_u[contact] - system.gap);
  } else {
    if (!(next[contact] > system.gap)) return false;
    if (contact_.lagrange()) {
      main_ = (next[contact] - system.gap) / (scale * contact_influence_[contact]);
    } else {
      ContactIterations iterations;
      main_ = single_contact_force(next[contact] - system.gap, scale * contact_influence_[contact],
                                   1.0 / contact_.main, contact_, iterations);
      list_law_.count(iterations);
    }
  }
  apply_last(system, 1.0, a);
  apply_last(system, scale, next);
  if (contact_.lagrange()) next[contact] = system.gap;
  return true;
}

void ExplicitStageContact::apply_last(const SecondOrderSystem& system, double factor,
                                      Eigen::VectorXd& x) {
  if (system.has_constraint_list()) {
    scaled_forces_ = factor * forces_;  // the same size: no allocation
    apply_constraint_forces(constraint_influence_, constraint_rows_, scaled_forces_, x);
    return;
  }
  if (main_ > 0.0) x -= (factor * main_) * contact_influence_;
  if (far_ > 0.0) x += (factor * far_) * far_influence_;
}

void ExplicitStageContact::write_last(const SecondOrderSystem& system, State& at) const {
  if (system.has_constraint_list()) {
    at.multipliers = forces_;  // the same size: no allocation
    at.lambda = 0.0;           // the list's are in multipliers
    return;
  }
  at.lambda = main_;
  if (system.has_far_contact()) at.far_lambda = far_;
}

void ExplicitStageContact::add_last(const SecondOrderSystem& system, State& at) const {
  if (system.has_constraint_list()) {
    at.multipliers += forces_;
    return;
  }
  at.lambda += main_;
  at.far_lambda += far_;
}

}  // namespace impactid
