// Tridiagonal matrices and their factorisation: every matrix of the 1D rod (mass, damping,
// stiffness, and the effective matrices of the integrators) is tridiagonal, so a step of
// any method costs O(n).
//
// Thread safety: the types are values; a const object may be shared between threads.
#pragma once

#include <Eigen/Core>

namespace impactid {

/// An n×n tridiagonal matrix stored by diagonals. lower(i) is A(i, i−1) (lower(0) unused),
/// upper(i) is A(i, i+1) (upper(n−1) unused).
struct Tridiagonal {
  Eigen::VectorXd lower;
  Eigen::VectorXd diag;
  Eigen::VectorXd upper;

  static Tridiagonal zero(Eigen::Index n);
  Eigen::Index size() const { return diag.size(); }
  /// True when both off-diagonals are exactly zero (a lumped mass matrix).
  bool is_diagonal() const;
  /// True when every entry is exactly zero (no damping).
  bool is_zero() const;

  /// Linear combination a·this + b·other (same size).
  Tridiagonal combined(double a, const Tridiagonal& other, double b) const;
  /// y = A·x, overwriting y. y must not alias x.
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  /// y += s·A·x. y must not alias x.
  void multiply_add(double s, const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  /// x^T A x, for energies.
  double quadratic_form(const Eigen::VectorXd& x) const;
  /// Dense copy, for tests and reference solvers.
  Eigen::MatrixXd dense() const;
};

/// The products under the names the sparse matrices' have (core/model/sparse_system.hpp), so that
/// a stepper written over the system (core/model/semi_discrete_system.hpp) calls either alike.
inline void multiply(const Tridiagonal& a, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  a.multiply(x, y);
}
inline void multiply_add(const Tridiagonal& a, double s, const Eigen::VectorXd& x,
                         Eigen::VectorXd& y) {
  a.multiply_add(s, x, y);
}
inline double quadratic_form(const Tridiagonal& a, const Eigen::VectorXd& x) {
  return a.quadratic_form(x);
}

/// LU factorisation without pivoting (the Thomas algorithm), stored so that each solve is two
/// sweeps of 3 and 4 flops per unknown, each sweep's recurrence one multiply and one add long
/// (the forward sweep divides by the pivot before eliminating; the back substitution runs two
/// rows at a time: core/algebra/tridiagonal.cpp). Valid for the diagonally dominant or symmetric
/// positive definite matrices that the integrators build; factor() reports a zero or non-finite
/// pivot.
class TridiagonalFactorization {
 public:
  /// Returns false (and leaves the object unusable) if a pivot is zero or not finite.
  bool factor(const Tridiagonal& a);
  /// Solves A·x = b in place (b becomes x). No allocation. The same as forward_in_place
  /// followed by backward_in_place.
  void solve_in_place(Eigen::VectorXd& b) const;
  /// The forward sweep alone: b becomes y with U·x = y (U the upper factor, unit diagonal). Its
  /// last entry is already x's last: a caller may change it (a constraint on the last unknown)
  /// before backward_in_place completes the solve.
  void forward_in_place(Eigen::VectorXd& b) const;
  /// The back substitution alone: y becomes x.
  void backward_in_place(Eigen::VectorXd& y) const;
  Eigen::Index size() const { return inverse_pivot_.size(); }
  /// Column j of A⁻¹ (the solution of A·x = e_j): the response to a unit point force, which the
  /// contact solvers scale. Allocates; for set-up, not for a step.
  Eigen::VectorXd inverse_column(Eigen::Index j) const;
  /// The stored factors, for the batched chain kernel (core/batch/chain_kernel.cpp), which sweeps
  /// with these very numbers lane by lane: 1/pivot_i, lower_i/pivot_i and c'_i = upper_i/pivot_i
  /// (it forms the products c'_i·c'_{i+1} again).
  const Eigen::VectorXd& inverse_pivots() const { return inverse_pivot_; }
  const Eigen::VectorXd& lower_ratios() const { return lower_ratio_; }
  const Eigen::VectorXd& upper_ratios() const { return upper_ratio_; }

 private:
  Eigen::VectorXd lower_ratio_;    // lower_i / pivot_i (row 0 unused)
  Eigen::VectorXd upper_ratio_;    // c'_i = upper_i / pivot_i
  Eigen::VectorXd upper_ratio2_;   // c'_i·c'_{i+1} (0 in the last two rows)
  Eigen::VectorXd inverse_pivot_;  // 1 / pivot_i
};

}  // namespace impactid
