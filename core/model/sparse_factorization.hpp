// The factorisation of a sparse symmetric positive definite matrix: the effective matrix of the
// implicit methods and the left-hand matrix of central difference on a user's model (issue 20),
// and M itself for the consistent initial acceleration.
//
// Eigen's SimplicialLDLT: the factorisation is done once per run and a step costs its two
// triangular solves. Its fill-reducing ordering is chosen per matrix, by the entries of L that
// each gives (both symbolic analyses are made; the numbers are then factored once): approximate
// minimum degree (AMD), or nested dissection by METIS (Debian's libmetis-dev) when that stores
// at least 10 % fewer (kMetisSaving). Below kMetisMinimumSize unknowns only AMD is analysed: a
// METIS analysis there takes about as long as the factorisation itself (the block: 8 ms against
// 3), a cost a sweep pays at every point, for no measurable gain. Measured (docs/performance.md, "The 3D beam"): on 3D models METIS
// stores 28 % fewer at 12,221 DOFs and 31 % at 46,529, and solves 1.2–1.3× faster; on the 2D
// block 5 % fewer with the same solve time, where AMD, the smaller ordering cost, stays. Why not CHOLMOD (Debian's
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
// Eigen 3.4's MetisSupport uses std::cerr without including <iostream>.
#include <iostream>
#include <Eigen/MetisSupport>
#include <Eigen/SparseCholesky>
#include <memory>
#include <string_view>
#include <variant>

#include "core/model/sparse_system.hpp"

namespace impactid {

/// The fill-reducing ordering a factorisation uses; "none" for a diagonal matrix.
enum class SparseOrdering { none, amd, metis };
std::string_view ordering_name(SparseOrdering ordering);

/// METIS is taken when its L stores at most this fraction of AMD's entries...
inline constexpr double kMetisSaving = 0.9;
/// ...on matrices of at least this many unknowns.
inline constexpr Eigen::Index kMetisMinimumSize = 10000;

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
  SparseOrdering ordering() const;
  Eigen::Index failed_dof() const { return failed_dof_; }
  double failed_pivot() const { return failed_pivot_; }
  /// Whether the matrix was diagonal; its solve is then b[i] *= inverse_diagonal()[i], which the
  /// batched model kernel (core/batch/batched_model.hpp) repeats lane by lane.
  bool diagonal() const { return diagonal_; }
  const Eigen::VectorXd& inverse_diagonal() const { return inverse_diagonal_; }

 private:
  // SimplicialLDLT with the entries of L its symbolic analysis found (Eigen keeps them per column).
  template <class Ordering>
  struct Ldlt : Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Ordering> {
    Eigen::Index analysed_entries() const { return this->m_nonZerosPerCol.sum(); }
  };
  using AmdLdlt = Ldlt<Eigen::AMDOrdering<int>>;
  using MetisLdlt = Ldlt<Eigen::MetisOrdering<int>>;

  Eigen::Index size_ = 0;
  bool diagonal_ = false;
  Eigen::VectorXd inverse_diagonal_;
  // The solver is not copyable; a workspace must stay movable. Empty for a diagonal matrix.
  std::variant<std::monostate, std::unique_ptr<AmdLdlt>, std::unique_ptr<MetisLdlt>> ldlt_;
  Eigen::VectorXd pivots_;      // D (Ldlt::vectorD returns a copy)
  mutable Eigen::VectorXd scratch_;
  Eigen::Index failed_dof_ = -1;
  double failed_pivot_ = 0.0;
};

}  // namespace impactid
