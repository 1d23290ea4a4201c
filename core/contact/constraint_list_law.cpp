#include "core/contact/constraint_list_law.hpp"

#include <algorithm>
#include <utility>

namespace impactid {

double constraint_violation(const Constraint& constraint, const Eigen::VectorXd& x) {
  double g = -constraint.gap;
  if (constraint.plus >= 0) g += x[constraint.plus];
  if (constraint.minus >= 0) g -= x[constraint.minus];
  return g;
}

void constraint_violations(const std::vector<Constraint>& constraints, const Eigen::VectorXd& x,
                           Eigen::VectorXd& violation) {
  const auto m = static_cast<Eigen::Index>(constraints.size());
  for (Eigen::Index j = 0; j < m; ++j) {
    violation[j] = constraint_violation(constraints[static_cast<std::size_t>(j)], x);
  }
}

void ConstraintListLaw::initialize(const ContactPenalties& contact, Eigen::Index constraints,
                                   PenaltyForm form, double weight) {
  contact_ = contact;
  form_ = form;
  iterations_ = unconverged_ = 0;
  violation_.resize(constraints);
  if (contact_.lagrange()) return;
  // The compliance of the weighted force w·μ: a spring k acting through the weight w.
  compliance_.resize(constraints);
  for (Eigen::Index j = 0; j < constraints; ++j) {
    compliance_[j] = 1.0 / (weight * contact_.listed[static_cast<std::size_t>(j)]);
  }
  shift_.resize(constraints);
  shifted_.resize(constraints);
}

ConstraintListProblem ConstraintListLaw::problem(Eigen::MatrixXd delassus) const {
  ConstraintListProblem out;
  out.delassus = std::move(delassus);
  const auto m = static_cast<int>(out.delassus.rows());
  out.delassus_diagonal = is_positive_diagonal(out.delassus.data(), m);
  if (!contact_.lagrange()) {
    out.penalized = out.delassus;
    out.penalized.diagonal() += compliance_;
    out.penalized_diagonal = is_positive_diagonal(out.penalized.data(), m);
  }
  return out;
}

void ConstraintListLaw::count(const ContactIterations& iterations) {
  iterations_ += iterations.iterations;
  if (!iterations.converged) ++unconverged_;
}

void ConstraintListLaw::solve(const ConstraintListProblem& problem, Eigen::VectorXd& forces,
                              ContactLcpWorkspace* lcp) {
  const auto m = static_cast<int>(violation_.size());
  // One LCP, with the workspace when there is one (the same operations either way), in O(m)
  // when D is diagonal (the same bits again).
  const auto solve_lcp = [&](const Eigen::MatrixXd& d, const double* p, double* mu) {
    if (&d == &problem.delassus ? problem.delassus_diagonal : problem.penalized_diagonal) {
      solve_diagonal_contact_lcp(d.data(), p, m, mu);
    } else if (lcp) {
      solve_contact_lcp(d.data(), p, m, mu, *lcp);
    } else {
      solve_contact_lcp(d.data(), p, m, mu);
    }
  };
  if (contact_.lagrange()) {
    solve_lcp(problem.delassus, violation_.data(), forces.data());
    return;
  }
  const bool penetrates = m > 0 && violation_.maxCoeff() > 0.0;
  if (contact_.law == ContactLaw::penalty) {
    if (form_ == PenaltyForm::solved_with_step) {
      solve_lcp(problem.penalized, violation_.data(), forces.data());
      return;
    }
    for (int j = 0; j < m; ++j) {
      forces[j] = contact_.listed[static_cast<std::size_t>(j)] * std::max(0.0, violation_[j]);
    }
    return;
  }
  if (!penetrates) {  // no penetration: no force
    if (form_ == PenaltyForm::solved_with_step) {
      solve_lcp(problem.penalized, violation_.data(), forces.data());
    } else {
      forces.setZero();
    }
    return;
  }
  // Uzawa's iterations: μ_{i+1} solves the penalised problem whose violations are shifted by
  // compliance·μ_i; the penetration μ leaves is p − D·μ.
  count(augmented_lagrangian(
      m, compliance_.data(), violation_.maxCoeff(), contact_.tolerance, contact_.max_iterations,
      forces.data(), shift_.data(),
      [&](const double* sh, double* out) {
        for (int j = 0; j < m; ++j) shifted_[j] = violation_[j] + sh[j];
        solve_lcp(problem.penalized, shifted_.data(), out);
      },
      [&](const double* out, int j) {
        double g = violation_[j];
        for (int i = 0; i < m; ++i) g -= problem.delassus(j, i) * out[i];
        return g;
      }));
}

bool ConstraintListLaw::forward_increment(const std::vector<Constraint>& constraints,
                                          const ConstraintListProblem& problem,
                                          const Eigen::VectorXd& next, const Eigen::VectorXd& at_u,
                                          Eigen::VectorXd& forces, ContactLcpWorkspace* lcp) {
  // The explicit spring's violations are those of the equilibrium's own displacement (its force
  // is explicit); the others' those of the next.
  const bool spring = contact_.law == ContactLaw::penalty && form_ == PenaltyForm::explicit_spring;
  constraint_violations(constraints, spring ? at_u : next, violation_);
  solve(problem, forces, lcp);
  return forces.size() > 0 && forces.maxCoeff() > 0.0;
}

}  // namespace impactid
