// The semi-discrete model of a user's finite element model (issue 20), of any sparsity:
//   M·ü + C·u̇ + K·u + Gᵀ·λ = f,   g_k = u[plus_k] − u[minus_k] − gap_k <= 0,  λ >= 0,  λ·g = 0,
// the form of SecondOrderSystem's constraint list (core/model/second_order_system.hpp) with M, C
// and K sparse instead of tridiagonal, and f the constant load (`load`: a model file's
// [scene.load], empty without one). M is symmetric positive definite, K symmetric positive
// semi-definite (rigid-body modes allowed), C symmetric (or absent).
//
// A model whose three matrices are tridiagonal (every 1D chain, the paper's rod exported as
// matrices) does not run here: core/model/model_scene.hpp turns it into a SecondOrderSystem, whose
// integrators are the O(n) Thomas solves the paper's scene has always used, with the same bits.
//
// Products and quadratic forms here never allocate: they run inside the step loop.
//
// Thread safety: values; const functions only.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <optional>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major, compressed

class SparseFactorization;  // core/model/sparse_factorization.hpp, which includes this header

struct SparseSystem {
  /// The matrices' type and the factorisation of the steppers' matrices (core/model/
  /// semi_discrete_system.hpp).
  using Matrix = SparseMatrix;
  using Factorization = SparseFactorization;

  SparseMatrix mass;
  SparseMatrix damping;  ///< no stored non-zero (or 0×0): no damping; integrators skip C terms
  SparseMatrix stiffness;
  std::vector<Constraint> constraints;
  /// A constant external force f (core/model/constant_load.hpp); empty: none.
  ConstantLoad load;

  Eigen::Index size() const { return mass.rows(); }
  bool has_damping() const { return damping.nonZeros() > 0; }
  /// ½·vᵀ·M·v + ½·uᵀ·K·u, and the load's potential V₀ − fᵀ·u when there is one
  double energy(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const;
};

/// Whether A is compressed and stores exactly its diagonal, one entry per column.
bool stores_diagonal_only(const SparseMatrix& a);
/// Whether A is compressed, each column's rows sorted, and A equals its transpose entry by entry,
/// bit for bit: then column i holds row i's entries in column order, and gathering it gives the
/// products a column-by-column scatter (multiply_add) adds to y[i], in the same order.
bool is_exactly_symmetric(const SparseMatrix& a);

/// y = A·x, overwriting y (sized n). y must not alias x.
void multiply(const SparseMatrix& a, const Eigen::VectorXd& x, Eigen::VectorXd& y);
/// y += s·A·x. y must not alias x.
void multiply_add(const SparseMatrix& a, double s, const Eigen::VectorXd& x, Eigen::VectorXd& y);
/// xᵀ·A·x.
double quadratic_form(const SparseMatrix& a, const Eigen::VectorXd& x);
/// True when no stored entry is off the diagonal with a non-zero value.
bool is_diagonal(const SparseMatrix& a);
/// The tridiagonal matrix equal to `a`, when no non-zero entry of `a` lies beyond its first
/// off-diagonals; nothing otherwise.
std::optional<Tridiagonal> as_tridiagonal(const SparseMatrix& a);
/// The sparse matrix equal to a tridiagonal one (explicit zeros dropped): export-model's.
SparseMatrix to_sparse(const Tridiagonal& a);

}  // namespace impactid
