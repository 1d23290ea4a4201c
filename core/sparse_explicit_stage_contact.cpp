#include "core/sparse_explicit_stage_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/constraint_set.hpp"       // snap_walls
#include "core/implicit_integrator.hpp"  // solve_listed_augmented
#include "core/sparse_constraints.hpp"
#include "core/stable_step.hpp"

namespace impactid {

bool SparseExplicitStageContact::initialize(const SparseSystem& system,
                                            const ContactPenalties& contact, double critical_omega,
                                            double dt) {
  contact_ = contact;
  iterations_ = unconverged_ = 0;
  failure_.clear();
  // Ω_crit over the Gershgorin bound on ω_max, with the penalty's springs (+inf, nothing
  // certified, for a mass that is not diagonal): ExplicitStageContact's.
  const double bound = highest_frequency_squared_bound(system, contact);
  if (!std::isfinite(bound)) {
    stable_step_ = 0.0;
    within_limit_ = false;
  } else {
    stable_step_ =
        bound > 0.0 ? critical_omega / std::sqrt(bound) : std::numeric_limits<double>::infinity();
    within_limit_ = dt * dt * bound <= critical_omega * critical_omega * (1.0 + 1e-12);
  }

  if (!mass_.factor(system.mass)) {
    failure_ = pivot_failure("the mass matrix", mass_);
    return false;
  }
  delassus_ = delassus_matrix(system.constraints, mass_, 1.0);
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  last_correction_.setZero(system.size());
  violation_.resize(m);
  forces_.setZero(m);
  lcp_.resize(static_cast<int>(m));
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    compliance_.resize(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      compliance_[j] = 1.0 / contact_.listed[static_cast<std::size_t>(j)];
    }
    shift_.resize(m);
    shifted_.resize(m);
  }
  return true;
}

StageProblem SparseExplicitStageContact::problem(double scale) const {
  StageProblem out;
  out.scale = scale;
  out.delassus = scale * delassus_;
  if (contact_.law == ContactLaw::augmented_lagrangian) {
    out.penalized = out.delassus;
    out.penalized.diagonal() += compliance_;
  }
  return out;
}

void SparseExplicitStageContact::solve_acceleration(const SparseSystem& system,
                                                    const Eigen::VectorXd& u,
                                                    const Eigen::VectorXd& v_predicted,
                                                    Eigen::VectorXd& a) const {
  multiply(system.stiffness, u, a);
  a = -a;
  if (system.has_damping()) multiply_add(system.damping, -1.0, v_predicted, a);
  mass_.solve_in_place(a);
}

void SparseExplicitStageContact::count(const ContactIterations& iterations) {
  iterations_ += iterations.iterations;
  if (!iterations.converged) ++unconverged_;
}

bool SparseExplicitStageContact::enforce(const SparseSystem& system, const StageProblem& problem,
                                         Eigen::VectorXd& a, Eigen::VectorXd& next,
                                         const Eigen::VectorXd& at_u) {
  const auto m = static_cast<int>(system.constraints.size());
  const bool penalty = contact_.law == ContactLaw::penalty;
  // The penalty's violations are those of the stage's own displacement (its force is explicit);
  // the others' those of the next.
  const Eigen::VectorXd& checked = penalty ? at_u : next;
  for (int j = 0; j < m; ++j) {
    const Constraint& con = system.constraints[static_cast<std::size_t>(j)];
    double g = -con.gap;  // ExplicitStageContact's order of operations
    if (con.plus >= 0) g += checked[con.plus];
    if (con.minus >= 0) g -= checked[con.minus];
    violation_[j] = g;
  }
  if (contact_.lagrange()) {
    solve_contact_lcp(problem.delassus.data(), violation_.data(), m, forces_.data(), lcp_);
  } else if (penalty) {
    for (int j = 0; j < m; ++j) {
      forces_[j] = contact_.listed[static_cast<std::size_t>(j)] * std::max(0.0, violation_[j]);
    }
  } else if (m > 0 && violation_.maxCoeff() > 0.0) {
    count(solve_listed_augmented(problem.delassus, problem.penalized, compliance_, violation_,
                                 contact_, forces_, shift_, shifted_, &lcp_));
  } else {
    forces_.setZero();
  }
  if (!(m > 0 && forces_.maxCoeff() > 0.0)) return false;
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
