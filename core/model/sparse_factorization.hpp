// The factorisation of a sparse symmetric positive definite matrix: the effective matrix of the
// implicit methods and the left-hand matrix of central difference on a user's model (issue 20),
// and M itself for the consistent initial acceleration.
//
// Eigen's SimplicialLDLT with an approximate minimum degree ordering (AMD): the factorisation is
// done once per run and a step costs its two triangular solves. Why not CHOLMOD (Debian's
// SuiteSparse), the alternative: it was slower on the shipped models, in its solves and mostly in
// its factorisation too (bench/model_bench.cpp times both; docs/performance.md, "User models"). A
// diagonal matrix (a lumped mass with central difference) is inverted entry by entry instead.
//
// A pivot that is not positive is reported with the DOF it belongs to (the ordering maps the
// elimination step back to the user's numbering): a mass matrix that is not positive definite,
// or an effective matrix made indefinite by a negative stiffness.
//
// Thread safety: one object per thread (solves use a scratch vector).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <memory>

#include "core/model/sparse_system.hpp"

namespace impactid {

class SparseFactorization {
 public:
  /// Factors `a` (symmetric; its lower triangle is read). Returns false when a pivot is not
  /// positive and finite: failed_dof() and failed_pivot() then say where.
  bool factor(const SparseMatrix& a);
  /// b becomes A⁻¹·b. No allocation after the first solve.
  void solve_in_place(Eigen::VectorXd& b) const;
  Eigen::Index size() const { return size_; }
  /// Stored entries of the factor L (n for a diagonal matrix): a solve costs about 4 flops each.
  Eigen::Index factor_nonzeros() const;
  Eigen::Index failed_dof() const { return failed_dof_; }
  double failed_pivot() const { return failed_pivot_; }

 private:
  using Ldlt = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>;
  Eigen::Index size_ = 0;
  bool diagonal_ = false;
  Eigen::VectorXd inverse_diagonal_;
  std::unique_ptr<Ldlt> ldlt_;  // the solver is not copyable; a workspace must stay movable
  Eigen::VectorXd pivots_;      // D (Ldlt::vectorD returns a copy)
  mutable Eigen::VectorXd scratch_;
  Eigen::Index failed_dof_ = -1;
  double failed_pivot_ = 0.0;
};

}  // namespace impactid
