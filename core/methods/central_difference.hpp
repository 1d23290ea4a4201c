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
// and both come from the 2×2 problem of core/algebra/two_wall_contact.hpp. With a lumped mass and
// no stiffness damping the left-hand matrix is diagonal, the two ends do not interact within a
// step, and this is Carpenter's multiplier at each end independently.
//
// With a list of constraints (scenes of several bodies) the forward-increment multipliers of every
// constraint come together from the complementarity problem of core/algebra/contact_lcp.hpp, with
// the left-hand matrix's columns A⁻¹·G_kᵀ factored in initialize(): the constraints hold at t + Δt
// and their multipliers are reported at t, as for the single wall.
//
// With a modified mass (core/model/rod_scene.hpp: redistributed, singular) the rod's contact DOFs
// carry no mass, and M/Δt² has a zero row there. Such a DOF is solved from its static equation
// within the step instead (GetFEM's demo_dynamic_contact_1D does the same for its explicit
// Newmark): the massive DOFs take the recurrence as always (the left-hand matrix gets a unit row
// at the massless DOF, which nothing couples to), then K_c·u_{t+Δt} ± λ_{t+Δt} = 0 gives the
// contact DOF at t + Δt from its neighbour's new position, on the wall with λ > 0 when its free
// static position would penetrate (core/contact/contact_treatment.hpp: massless_contact_force).
// That λ is the force at t + Δt, reported with the next sample, so the pressure at t_i is still
// the multiplier at t_i. Damping on such a DOF is refused (its static equation would need its
// velocity): massless_failure().
//
// Paoli–Schatzman's law (ContactPenalties::restitution e > 0, core/contact/paoli_schatzman_law.hpp)
// is the same forward increment on every wall and constraint with each gap shifted by −e·g(u₋),
// the violation of the previous displacement, so that the gap holds on (u₊ + e·u₋)/(1 + e); each
// pushed DOF is snapped onto its shifted wall. It is not defined on a massless DOF, whose static
// equation has no u₋ (refused in initialize()).
//
// Written once with the sparse stepper (SparseCentralDifference, core/methods/
// sparse_integrators.hpp): the start, the contact-free update, the sample and the energy
// (core/methods/central_difference_recurrence.hpp, over any core/model/semi_discrete_system.hpp).
// The forward-increment contact between them stays one class per system, for the reason
// core/methods/implicit_integrator.hpp gives: stored columns A⁻¹·G_kᵀ here (and the named walls'
// O(1) shortcuts), one more solve there, different operations whose bits the batched kernel
// (core/batch/cdm_kernel.hpp) and the results files hold fixed.
//
// Thread safety: one object per thread.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/central_difference_recurrence.hpp"
#include "core/methods/method.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

class CentralDifference {
 public:
  /// Factors the left-hand matrix and starts from `initial` at t₀ with u₋ = u₀ − Δt·v₀ +
  /// ½Δt²·a₀ (a₀ must be consistent). Returns false if the matrix is singular.
  /// `contact` says how the constraints are enforced (core/contact/contact_treatment.hpp):
  /// Lagrange's forward increment (default), the explicit penalty force k·max(0, g(u_t)) at t, or
  /// Uzawa's iterations on the forward increment's penalty problem.
  bool initialize(const SecondOrderSystem& system, CdmVelocity velocity, double dt,
                  const State& initial, const ContactPenalties& contact = {});

  /// Computes λ_t and u_{t+Δt} and fills `at_t` with the state at the current time t
  /// (u, the velocity of the chosen variant, a = (u₊ − 2u + u₋)/Δt², λ_t, t), then moves on
  /// to t + Δt. The state at t is only complete once u_{t+Δt} is known, hence this shape.
  /// Returns true if λ_t > 0 (the main wall's; a far wall's λ_0 at t is at_t.far_lambda).
  bool step(const SecondOrderSystem& system, State& at_t);

  /// The energy the step loop's `unstable` test and the history's energy column use for the state
  /// `at_t` the last step() filled in: within the explicit limit certified by
  /// core/contact/stable_step.hpp, the method's own energy at t + Δt/2 (central_difference_energy
  /// of u_t and u_{t+Δt}); otherwise the plain ½vᵀMv + ½uᵀKu of `at_t`, which reacts sooner to a
  /// mode that grows geometrically than central_difference_energy's absolute value does
  /// (tests/central_difference_test.cpp, UnstableRunsStopNoLaterThanByThePlainEnergy). O(n), no
  /// allocation.
  double energy(const SecondOrderSystem& system, const State& at_t);
  /// Whether Δt is within the explicit limit (core/contact/stable_step.hpp) on this system, with
  /// the penalty's springs.
  bool within_stability_limit() const { return within_limit_; }
  /// The largest step certified stable (core/contact/stable_step.hpp: 2/ω_bound) [s], with the
  /// penalty's springs; 0 when none can be certified (a mass that is not diagonal).
  double stable_step() const { return stable_step_; }
  /// As ImplicitIntegrator's: augmented-Lagrangian iterations, and steps that hit the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }
  /// Why initialize() failed: a singular left-hand matrix, or a massless DOF it cannot step.
  const std::string& failure() const { return failure_; }

 private:
  /// step() on a rod whose contact DOFs are massless (above).
  bool step_massless(const SecondOrderSystem& system, State& at_t);
  /// A wall's gap for this step: `gap` shifted by Paoli–Schatzman's −e·g(u₋) (g(u₋) =
  /// `previous_violation`), `gap` itself under every other law.
  double shifted_gap(double gap, double previous_violation) const;
  /// Why a system with massless DOFs cannot be stepped, or "" if it can.
  static std::string massless_failure(const SecondOrderSystem& system);

  CentralDifferenceRecurrence recurrence_;  // the update formulas, u₋, u and u₊
  bool within_limit_ = false;
  TridiagonalFactorization factorization_;
  Eigen::VectorXd contact_influence_;  // A⁻¹·e_c
  Eigen::VectorXd far_influence_;      // A⁻¹·e_far; empty without a far wall
  // The constraint list's columns, their non-zero rows, G·A⁻¹·Gᵀ and per-step scratch.
  Eigen::MatrixXd constraint_influence_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> constraint_rows_;
  ConstraintListProblem list_;  // G·A⁻¹·Gᵀ (with the springs' compliances: penalty laws)
  Eigen::VectorXd forces_;
  Eigen::VectorXd gap_shifts_;  // Paoli–Schatzman's −e·g_j(u₋) of the listed constraints
  ContactPenalties contact_;
  ConstraintListLaw list_law_;  // the list's law; counts every solve's Uzawa iterations
  double stable_step_ = 0.0;
  // Massless contact DOFs (a modified mass): whether the main and the far wall's DOF are, and the
  // forces their static equations gave at t + Δt, reported with the next sample.
  bool massless_main_ = false, massless_far_ = false;
  double next_lambda_ = 0.0, next_far_lambda_ = 0.0;
  std::string failure_;
};

}  // namespace impactid
