#include "core/model/sparse_factorization.hpp"

#include <cmath>
#include <type_traits>

namespace impactid {

std::string_view ordering_name(SparseOrdering ordering) {
  switch (ordering) {
    case SparseOrdering::none:
      return "none";
    case SparseOrdering::amd:
      return "amd";
    case SparseOrdering::metis:
      return "metis";
  }
  return "none";
}

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
    ldlt_ = std::monostate{};
    return true;
  }
  auto amd = std::make_unique<AmdLdlt>();
  amd->analyzePattern(a);
  ldlt_ = std::move(amd);
  if (size_ >= kMetisMinimumSize) {
    auto metis = std::make_unique<MetisLdlt>();
    metis->analyzePattern(a);
    const auto amd_entries = std::get<1>(ldlt_)->analysed_entries();
    // A METIS failure leaves no permutation (Eigen then says so on stderr): AMD stays.
    if (metis->permutationP().size() == size_ &&
        static_cast<double>(metis->analysed_entries()) <=
            kMetisSaving * static_cast<double>(amd_entries)) {
      ldlt_ = std::move(metis);
    }
  }
  return std::visit(
      [&](auto& ldlt) {
        if constexpr (std::is_same_v<std::decay_t<decltype(ldlt)>, std::monostate>) {
          return false;
        } else {
          ldlt->factorize(a);
          // A negative pivot does not stop SimplicialLDLT; it is found in D, as a zero one is.
          // The factorisation stops at an exactly zero pivot, having written it to D; D's
          // entries past it are not set, so the scan stops at the first bad one.
          pivots_ = ldlt->vectorD();
          for (Eigen::Index k = 0; k < size_; ++k) {
            if (!(pivots_[k] > 0.0) || !std::isfinite(pivots_[k])) {
              // P·A·Pᵀ = L·D·Lᵀ: elimination step k is the row of A that P sends to k.
              failed_dof_ = ldlt->permutationPinv().indices()[k];
              failed_pivot_ = pivots_[k];
              return false;
            }
          }
          scratch_.resize(size_);
          return true;
        }
      },
      ldlt_);
}

void SparseFactorization::solve_in_place(Eigen::VectorXd& b) const {
  if (diagonal_) {
    b.array() *= inverse_diagonal_.array();
    return;
  }
  std::visit(
      [&](const auto& ldlt) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(ldlt)>, std::monostate>) {
          // Ldlt::solve's last permutation is applied in place, which allocates a mask per
          // solve: the same steps here with the permutations applied into and out of the
          // scratch vector.
          const auto& p = ldlt->permutationP().indices();
          const auto& p_inv = ldlt->permutationPinv().indices();
          for (Eigen::Index i = 0; i < size_; ++i) scratch_[p[i]] = b[i];
          ldlt->matrixL().solveInPlace(scratch_);
          scratch_.array() /= pivots_.array();
          ldlt->matrixU().solveInPlace(scratch_);
          for (Eigen::Index k = 0; k < size_; ++k) b[p_inv[k]] = scratch_[k];
        }
      },
      ldlt_);
}

Eigen::Index SparseFactorization::factor_nonzeros() const {
  if (diagonal_) return size_;
  return std::visit(
      [](const auto& ldlt) -> Eigen::Index {
        if constexpr (std::is_same_v<std::decay_t<decltype(ldlt)>, std::monostate>) {
          return 0;
        } else {
          return ldlt->matrixL().nestedExpression().nonZeros();
        }
      },
      ldlt_);
}

SparseOrdering SparseFactorization::ordering() const {
  switch (ldlt_.index()) {
    case 1:
      return SparseOrdering::amd;
    case 2:
      return SparseOrdering::metis;
    default:
      return SparseOrdering::none;
  }
}

}  // namespace impactid
