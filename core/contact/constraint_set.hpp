// What both integrators do with a list of constraints (SecondOrderSystem::constraints): the
// influence columns A⁻¹·G_kᵀ of their step matrix A, computed once per run, and the per-step
// correction by the contact forces. Shared so that central difference and the implicit family
// treat the constraints by the same operations.
//
// Thread safety: free functions on caller-owned storage.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

/// Columns A⁻¹·G_kᵀ (n × m), the rows [begin, end) outside which each is exactly zero, and the
/// Delassus matrix scale·G·A⁻¹·Gᵀ (m × m). Allocates: for set-up only.
void set_up_constraints(const SecondOrderSystem& system, const TridiagonalFactorization& a,
                        double scale, Eigen::MatrixXd& influence,
                        std::vector<std::pair<Eigen::Index, Eigen::Index>>& rows,
                        Eigen::MatrixXd& delassus);

/// x −= Σ_k forces_k · influence_k, over each column's non-zero rows; no allocation.
void apply_constraint_forces(const Eigen::MatrixXd& influence,
                             const std::vector<std::pair<Eigen::Index, Eigen::Index>>& rows,
                             const Eigen::VectorXd& forces, Eigen::VectorXd& x);

/// Puts a wall's dof exactly on its wall where the wall pushes (round-off would leave it a few
/// ulps off); a constraint between two bodies is left as computed (neither dof is fixed).
void snap_walls(const std::vector<Constraint>& constraints, const Eigen::VectorXd& forces,
                Eigen::VectorXd& u);
/// The same with each wall's gap shifted by gap_offsets[k] (ImplicitIntegrator::gap_offsets());
/// zero offsets snap to the same bits.
void snap_walls(const std::vector<Constraint>& constraints, const Eigen::VectorXd& forces,
                Eigen::VectorXd& u, const Eigen::VectorXd& gap_offsets);

}  // namespace impactid
