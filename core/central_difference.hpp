// Central difference with Carpenter's forward-increment Lagrange multiplier (Carpenter, Taylor
// & Katona 1991, doi:10.1002/nme.1620320107; paper eqs 3–7): the multiplier λ_t is the force
// at t that puts the contact dof exactly on the wall at t + Δt when the contact-free update
// would penetrate it, and zero otherwise.
//
// Update at t (velocity variants of CdmVelocity):
//   central:  (M/Δt² + C/(2Δt))·u₊ = M·(2u − u₋)/Δt² + C·u₋/(2Δt) − K·u − G^T·λ_t   (eq. 5)
//   backward:  M/Δt²·u₊          = M·(2u − u₋)/Δt² − C·(u − u₋)/Δt − K·u − G^T·λ_t (eq. 7)
// The left-hand matrix is diagonal for a lumped mass without stiffness damping, tridiagonal
// otherwise; it is factored once. Stable for Courant numbers below 1 (lumped, undamped): the
// highest mode of the lumped rod has Ω = ω·Δt = 2·Courant, and at exactly Ω = 2 its repeated
// eigenvalue −1 grows linearly.
//
// With a far wall the same forward-increment multiplier acts at node 0 too (λ_0 >= 0, force +λ_0),
// and both come from the 2×2 problem of core/two_wall_contact.hpp. With a lumped mass and no
// stiffness damping the left-hand matrix is diagonal, the two ends do not interact within a step,
// and this is Carpenter's multiplier at each end independently.
//
// With a list of constraints (scenes of several bodies) the forward-increment multipliers of every
// constraint come together from the complementarity problem of core/contact_lcp.hpp, with the
// left-hand matrix's columns A⁻¹·G_kᵀ factored in initialize(): the constraints hold at t + Δt
// and their multipliers are reported at t, as for the single wall.
//
// Thread safety: one object per thread.
#pragma once

#include <utility>
#include <vector>

#include "core/method.hpp"
#include "core/second_order_system.hpp"
#include "core/state.hpp"
#include "core/tridiagonal.hpp"

namespace impactid {

class CentralDifference {
 public:
  /// Factors the left-hand matrix and starts from `initial` at t₀ with u₋ = u₀ − Δt·v₀ +
  /// ½Δt²·a₀ (a₀ must be consistent). Returns false if the matrix is singular.
  bool initialize(const SecondOrderSystem& system, CdmVelocity velocity, double dt,
                  const State& initial);

  /// Computes λ_t and u_{t+Δt} and fills `at_t` with the state at the current time t
  /// (u, the velocity of the chosen variant, a = (u₊ − 2u + u₋)/Δt², λ_t, t), then moves on
  /// to t + Δt. The state at t is only complete once u_{t+Δt} is known, hence this shape.
  /// Returns true if λ_t > 0 (the main wall's; a far wall's λ_0 at t is at_t.far_lambda).
  bool step(const SecondOrderSystem& system, State& at_t);

 private:
  CdmVelocity velocity_ = CdmVelocity::central;
  double dt_ = 0.0;
  double t_ = 0.0;
  TridiagonalFactorization factorization_;
  Eigen::VectorXd contact_influence_;  // A⁻¹·e_c
  Eigen::VectorXd far_influence_;      // A⁻¹·e_far; empty without a far wall
  Eigen::VectorXd u_previous_, u_, u_next_, scratch_;
  // The constraint list's columns, their non-zero rows, G·A⁻¹·Gᵀ and per-step scratch.
  Eigen::MatrixXd constraint_influence_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> constraint_rows_;
  Eigen::MatrixXd delassus_;
  Eigen::VectorXd violation_, forces_;
};

}  // namespace impactid
