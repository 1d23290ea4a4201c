#include "core/contact/sparse_explicit_stage_contact.hpp"

#include "core/contact/constraint_set.hpp"  // snap_walls
#include "core/contact/sparse_constraints.hpp"
#include "core/contact/stable_step.hpp"

namespace impactid {

bool SparseExplicitStageContact::initialize(const SparseSystem& system,
                                            const ContactPenalties& contact, double critical_omega,
                                            double dt) {
  contact_ = contact;
  failure_.clear();
  // Ω_crit over the Gershgorin bound on ω_max, with the penalty's springs.
  const StageStableStep stable =
      stage_stable_step(highest_frequency_squared_bound(system, contact), critical_omega, dt);
  stable_step_ = stable.step;
  within_limit_ = stable.within;

  if (!mass_.factor(system.mass)) {
    failure_ = pivot_failure("the mass matrix", mass_);
    return false;
  }
  delassus_ = delassus_matrix(system.constraints, mass_, 1.0);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  last_correction_.setZero(system.size());
  list_law_.initialize(contact_, m, PenaltyForm::explicit_spring);
  forces_.setZero(m);
  lcp_.resize(static_cast<int>(m));
  return true;
}

StageProblem SparseExplicitStageContact::problem(double scale) const {
  return {scale, list_law_.problem(scale * delassus_)};
}

void SparseExplicitStageContact::solve_acceleration(const SparseSystem& system,
                                                    const Eigen::VectorXd& u,
                                                    const Eigen::VectorXd& v_predicted,
                                                    Eigen::VectorXd& a) const {
  multiply(system.stiffness, u, a);
  a = -a;
  if (system.load.active()) a += system.load.force;
  if (system.has_damping()) multiply_add(system.damping, -1.0, v_predicted, a);
  mass_.solve_in_place(a);
}

bool SparseExplicitStageContact::enforce(const SparseSystem& system, const StageProblem& problem,
                                         Eigen::VectorXd& a, Eigen::VectorXd& next,
                                         const Eigen::VectorXd& at_u) {
  // ExplicitStageContact's law and order of operations; the correction M⁻¹·Gᵀ·λ by one solve.
  if (!list_law_.forward_increment(system.constraints, problem.list, next, at_u, forces_, &lcp_)) {
    return false;
  }
  last_correction_.setZero();
  add_constraint_forces(system.constraints, forces_, 1.0, last_correction_);
  mass_.solve_in_place(last_correction_);  // M⁻¹·Gᵀ·λ
  a -= last_correction_;
  next -= problem.scale * last_correction_;
  if (contact_.lagrange()) snap_walls(system.constraints, forces_, next);
  return true;
}

void SparseExplicitStageContact::apply_last(const SparseSystem&, double factor,
                                            Eigen::VectorXd& x) {
  x -= factor * last_correction_;
}

void SparseExplicitStageContact::write_last(const SparseSystem&, State& at) const {
  at.multipliers = forces_;  // the same size: no allocation
  at.lambda = 0.0;           // the list's are in multipliers
}

void SparseExplicitStageContact::add_last(const SparseSystem&, State& at) const {
  at.multipliers += forces_;
}

}  // namespace impactid
