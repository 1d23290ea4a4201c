#include "core/model/sparse_factorization.hpp"

#include <cmath>

namespace impactid {

bool SparseFactorization::factor(const SparseMatrix& a) {
  size_ = a.rows();
  failed_dof_ = -1;
  failed_pivot_ = 0.0;
  diagonal_ = is_diagonal(a);
  if (diagonal_) {
    const Eigen::VectorXd d = a.diagonal();
    for (Eigen::Index i = 0; i < size_; ++i) {
      if (!(d[i] > 0.0) || !std::isfinite(d[i])) {
        failed_dof_ = i;
        failed_pivot_ = d[i];
        return false;
      }
    }
    inverse_diagonal_ = d.cwiseInverse();
    ldlt_.reset();
    return true;
  }
  if (!ldlt_) ldlt_ = std::make_unique<Ldlt>();
  ldlt_->compute(a);
  // A negative pivot does not stop SimplicialLDLT; it is found in D, as a zero one is.
  // The factorisation stops at an exactly zero pivot, having written it to D; D's entries past
  // it are not set, so the scan stops at the first bad one.
  pivots_ = ldlt_->vectorD();
  for (Eigen::Index k = 0; k < size_; ++k) {
    if (!(pivots_[k] > 0.0) || !std::isfinite(pivots_[k])) {
      // P·A·Pᵀ = L·D·Lᵀ: elimination step k is the row of A that P sends to k.
      failed_dof_ = ldlt_->permutationPinv().indices()[k];
      failed_pivot_ = pivots_[k];
      return false;
    }
  }
  scratch_.resize(size_);
  return true;
}

void SparseFactorization::solve_in_place(Eigen::VectorXd& b) const {
  if (diagonal_) {
    b.array() *= inverse_diagonal_.array();
    return;
  }
  // Ldlt::solve's last permutation is applied in place, which allocates a mask per solve: the
  // same steps here with the permutations applied into and out of the scratch vector.
  const auto& p = ldlt_->permutationP().indices();
  const auto& p_inv = ldlt_->permutationPinv().indices();
  for (Eigen::Index i = 0; i < size_; ++i) scratch_[p[i]] = b[i];
  ldlt_->matrixL().solveInPlace(scratch_);
  scratch_.array() /= pivots_.array();
  ldlt_->matrixU().solveInPlace(scratch_);
  for (Eigen::Index k = 0; k < size_; ++k) b[p_inv[k]] = scratch_[k];
}

Eigen::Index SparseFactorization::factor_nonzeros() const {
  return diagonal_ ? size_ : ldlt_->matrixL().nestedExpression().nonZeros();
}

}  // namespace impactid
