// A contact law (core/contact/contact_treatment.hpp) applied to a list of m constraints (scenes of
// bodies, two walls of a model, a user's model): the one place where every stepper's list turns
// its violations into forces. A step measures each constraint's violation of its contact-free
// prediction, g_j = −gap_j + u[plus_j] − u[minus_j] (> 0: penetration), and the forces μ >= 0
// then solve the step's complementarity problem g = p − D·μ (D the Delassus matrix of the
// method's step operator, core/algebra/contact_lcp.hpp), by the law:
// - **lagrange**: LCP(−p, D) by Murty's pivoting; the gaps hold exactly.
// - **penalty**, in one of two forms, fixed at initialize() by the method:
//   - `PenaltyForm::solved_with_step` (the implicit methods, KR-α's forward increment): the same
//     LCP with D + diag(compliance), the spring solved with the step;
//   - `PenaltyForm::explicit_spring` (central difference, the explicit stages):
//     μ_j = k_j·max(0, g_j) of the violation at the displacement the equilibrium is taken at; no
//     solve.
// - **augmented-lagrangian**: Uzawa's iterations (core/contact/contact_treatment.hpp) on the
//   penalised problem (D + C)·μ = p + C·μ_i, C = diag(compliance), counted here.
// compliance_j = 1/(w·k_j): the spring k_j acting through the weight w the method gives its
// forces (ImplicitCoefficients::contact_weight; 1 for the explicit methods).
//
// What stays with the steppers is what differs between them: how D is formed and how a force
// moves the state (the columns A⁻¹·Gᵀ kept on a tridiagonal system, one more solve with the
// factorised matrix on a sparse one), and the snapping of the walls' DOFs (Lagrange only).
//
// No allocation once initialize() and problem() have sized all: a step costs the LCP (or m
// multiplications for the explicit springs, Uzawa's iterations of LCPs for the augmented one).
//
// Thread safety: one object per thread (it holds scratch vectors and counters).
#pragma once

#include <vector>

#include "core/algebra/contact_lcp.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

/// How a method applies the penalty's springs to a constraint list.
enum class PenaltyForm {
  solved_with_step,  ///< implicit: the LCP with D + diag(compliance)
  explicit_spring,   ///< explicit: k·max(0, g) of the equilibrium's own displacement
};

/// One step's (or stage's) problem of a constraint list: its Delassus matrix, scaled as the
/// method's step needs, and for the penalty laws D + diag(compliance).
struct ConstraintListProblem {
  Eigen::MatrixXd delassus;   ///< m × m, symmetric positive definite
  Eigen::MatrixXd penalized;  ///< D + diag(compliance); empty for lagrange
  /// Each is_positive_diagonal (core/algebra/contact_lcp.hpp): its LCP is solved in O(m).
  bool delassus_diagonal = false, penalized_diagonal = false;
};

/// g = −gap + x[plus] − x[minus] of one constraint (> 0: penetration), in this order of operations
/// (the steppers' bits).
double constraint_violation(const Constraint& constraint, const Eigen::VectorXd& x);
/// constraint_violation() of every listed constraint. `violation` has m entries; no allocation.
void constraint_violations(const std::vector<Constraint>& constraints, const Eigen::VectorXd& x,
                           Eigen::VectorXd& violation);

class ConstraintListLaw {
 public:
  /// Keeps the law, each constraint's compliance 1/(weight·k_j) (penalty laws) and sizes the
  /// scratch for `constraints` constraints; zeroes the counters. Allocates: set-up only.
  void initialize(const ContactPenalties& contact, Eigen::Index constraints, PenaltyForm form,
                  double weight = 1.0);
  /// The problem with the Delassus matrix `delassus` (and D + diag(compliance) unless the law
  /// is Lagrange's). Allocates: set-up only.
  ConstraintListProblem problem(Eigen::MatrixXd delassus) const;

  /// The violations a step fills in before solve() (m entries), when it measures them its own
  /// way (the implicit integrators' fused multiply-adds, a gap offset).
  Eigen::VectorXd& violation() { return violation_; }
  /// The forces μ (m entries) of violation() under the law; Uzawa's iterations are counted.
  /// `lcp`: the workspace of a problem of any size (a user's model); without one,
  /// m <= kMaxConstraints.
  void solve(const ConstraintListProblem& problem, Eigen::VectorXd& forces,
             ContactLcpWorkspace* lcp = nullptr);
  /// A forward increment's forces (the explicit methods): violations of the contact-free `next`
  /// displacement, or with the explicit spring of `at_u` (the displacement the equilibrium is
  /// taken at), then solve(). Returns whether a constraint pushes (some μ_j > 0).
  bool forward_increment(const std::vector<Constraint>& constraints,
                         const ConstraintListProblem& problem, const Eigen::VectorXd& next,
                         const Eigen::VectorXd& at_u, Eigen::VectorXd& forces,
                         ContactLcpWorkspace* lcp = nullptr);

  /// Adds the iterations of a solve outside the list (one wall, two walls) to the counters.
  void count(const ContactIterations& iterations);
  /// Augmented-Lagrangian iterations since initialize(), and the solves that hit the cap.
  long iterations() const { return iterations_; }
  long unconverged() const { return unconverged_; }

 private:
  ContactPenalties contact_;
  PenaltyForm form_ = PenaltyForm::solved_with_step;
  Eigen::VectorXd violation_;
  Eigen::VectorXd compliance_, shift_, shifted_;  // penalty laws (m)
  long iterations_ = 0, unconverged_ = 0;
};

}  // namespace impactid
