// What the integrators on a user's sparse model (core/model/sparse_system.hpp) do with its
// constraint list, G·u − gap <= 0: the forces Gᵀ·f, the rows G·x, the Delassus matrix
// scale·G·A⁻¹·Gᵀ of a factorised step matrix A, and a factorisation's failure message. The sparse
// counterpart of core/contact/constraint_set.hpp: there the columns A⁻¹·G_kᵀ of a tridiagonal A are
// kept, here they are not (they are dense for a 2D or 3D model, core/methods/sparse_integrators.hpp
// says why), and a force acts through one more solve with Gᵀ·f as the right-hand side.
//
// Thread safety: free functions on caller-owned storage.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/second_order_system.hpp"
#include "core/model/sparse_factorization.hpp"

namespace impactid {

/// v[plus_k] += s·f_k, v[minus_k] −= s·f_k: s·Gᵀ·f added to v. No allocation.
void add_constraint_forces(const std::vector<Constraint>& constraints, const Eigen::VectorXd& f,
                           double s, Eigen::VectorXd& v);
/// G·x of one constraint (its gap left out).
double constraint_row(const Constraint& c, const Eigen::VectorXd& x);
/// scale·G·A⁻¹·Gᵀ, one solve per constraint; exactly symmetric. Allocates: set-up only.
Eigen::MatrixXd delassus_matrix(const std::vector<Constraint>& constraints,
                                const SparseFactorization& a, double scale);
/// "WHAT is not positive definite: pivot P at DOF D", naming the failed pivot's DOF (0-based, as
/// the scene files count).
std::string pivot_failure(const char* what, const SparseFactorization& f);

}  // namespace impactid
