// The Noh–Bathe explicit scheme (Noh & Bathe 2013, "An explicit time integration scheme for the
// analysis of wave propagations", Computers & Structures 129:178–193,
// doi:10.1016/j.compstruc.2013.06.007; formulas, range of p and stability limit at NohBatheParams,
// core/methods/method.hpp) on the tridiagonal systems (the rod, scenes of bodies, a model of
// tridiagonal matrices: NohBatheExplicit) and on a user's model of sparse matrices
// (core/model/sparse_system.hpp: SparseNohBatheExplicit), with the three contact laws of
// core/contact/contact_treatment.hpp. Both are one template over the stage contact
// (core/contact/explicit_stage_contact.hpp, core/contact/sparse_explicit_stage_contact.hpp), so
// they step by the same formulas and contact conventions; on a sparse model the constraints are
// always a list, M is factored once per run by core/model/sparse_factorization.hpp (entry by entry
// when lumped), and a stage's force acts through one more solve with M instead of stored columns.
//
// Contact (Lagrange multipliers, the default): a forward increment at each sub-step, as central
// difference's (Carpenter, Taylor & Katona 1991, core/methods/central_difference.hpp). The
// acceleration a sub-step computes fixes the displacement at the next point of the time grid
// t, t + pΔt, t + Δt, t + Δt + pΔt, …, linearly:
//   sub-step 1 (equilibrium at t + pΔt):  u₁ = u_p + (1−p)Δt·(v₀ + pΔt/2·a₀) + c₁·a_p,
//                                         c₁ = (1−p)Δt·pΔt/2 + ((1−p)Δt)²/2 = (1−p)Δt²/2;
//   sub-step 2 (equilibrium at t + Δt):   u_{1+p} = u₁ + pΔt·v₁ + (pΔt)²/2·a₁
//                                         = (terms without a₁) + c₂·a₁,
//                                         c₂ = Δt²·p·((1−p)·q2 + p/2).
// Each sub-step's multipliers λ >= 0 are the forces in its equilibrium (M·a = −K·u − C·ṽ − Gᵀλ)
// that put that next displacement exactly on the wall where the contact-free one would penetrate:
// the complementarity problem g_next − c·G·M⁻¹·Gᵀ·λ <= 0, λ >= 0, complementary (one wall: one
// division; two walls: core/algebra/two_wall_contact.hpp; a list: core/algebra/contact_lcp.hpp,
// Delassus matrix c·G·M⁻¹·Gᵀ). The displacement of the next point is computed once, there, snapped
// onto its wall, and used as such by the following sub-step (it equals the scheme's formula for it
// up to round-off). So:
//   - the constraints hold at every point of the grid: at each sample t + Δt (enforced by the
//     multiplier at t + pΔt) and at each sub-step t + pΔt (by the multiplier at t);
//   - the multiplier reported with the sample t + Δt is that of its own equilibrium, λ₁ >= 0,
//     complementary to the gap at the next sub-step t + Δt + pΔt (as central difference's λ_t is
//     to the gap at t + Δt); the sub-step's λ_p (substep_state()) is complementary to the gap at
//     t + Δt.
// Why a forward increment: an explicit sub-step cannot change its own displacement, which the
// previous one fixed; the force it can still choose acts on the next. Enforcing it at both
// sub-steps keeps every point of the grid admissible, so that neither sub-step starts from a
// penetrating state (see core/methods/bathe_composite.hpp for what that costs the implicit
// composites). The first sub-step's displacement u_p of the first step is fixed in initialize() the
// same way, by a multiplier at the start (coefficient (pΔt)²/2), which then belongs to the start's
// acceleration.
//
// Penalty: at each sub-step the explicit spring force λ = k·max(0, g) of the displacement its
// equilibrium is taken at (u_p at t + pΔt, u₁ at t + Δt), as central difference's at t; so the
// multiplier reported with the sample t + Δt is the spring of the sample's own penetration. The
// springs raise ω_max: the stable step Ω_crit(p)/ω_bound uses core/contact/stable_step.hpp's bound
// with them, and a step above it is flagged before the run starts. Augmented Lagrangian: Uzawa's
// iterations on each sub-step's forward-increment problem with the springs' compliances
// (core/contact/explicit_stage_contact.hpp), counted in the run summary. Neither snaps a node onto
// its wall.
//
// Per step: two solves with the factorised M (diagonal for a lumped mass), two products with K
// (and with C when damped), O(n) vector work (on a sparse model, O(nnz) products, and one more
// solve per sub-step whose contact pushes), no allocation once sized (initialize sizes all).
//
// Thread safety: one object per thread.
#pragma once

#include "core/common/state.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/contact/explicit_stage_contact.hpp"
#include "core/contact/sparse_explicit_stage_contact.hpp"
#include "core/methods/method.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/semi_discrete_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// The scheme on a `System` (SecondOrderSystem or SparseSystem) whose stages' contact is a
/// `StageContact` (ExplicitStageContact or SparseExplicitStageContact); the aliases below.
template <class StageContact, SemiDiscreteSystem System>
class NohBatheScheme {
 public:
  /// Factors M and fixes the first sub-step's displacement u_p = u₀ + pΔt·v₀ + (pΔt)²/2·a₀ from
  /// `start` (a₀ consistent), with the contact at the start (the header): start.a and its
  /// multipliers (lambda, far_lambda or multipliers) then include that force. False if M is
  /// singular (on a sparse model not positive definite: stage_contact().failure() says where).
  /// `contact` says how the constraints are enforced (the header; default Lagrange).
  bool initialize(const System& system, const NohBatheCoefficients& coefficients, double dt,
                  State& start, const ContactPenalties& contact = {});

  /// Advances state from t to t + Δt (u, v, a and the multipliers of the equilibrium at t + Δt).
  /// Returns true if a constraint pushes at t + Δt.
  bool step(const System& system, State& state);

  /// The state at t + pΔt of the last step (u_p, v_p, a_p, its multipliers, t + pΔt).
  const State& substep_state() const { return sub_; }
  /// The largest step certified stable without damping: Ω_crit(p)/ω_bound with
  /// core/contact/stable_step.hpp's Gershgorin bound ω_bound on ω_max [s]; 0 when none can be
  /// certified (a mass that is not diagonal).
  double stable_step() const { return contact_.stable_step(); }
  /// Whether Δt is within stable_step() (up to a relative 1e-12).
  bool within_stability_limit() const { return contact_.within_stability_limit(); }
  /// Augmented-Lagrangian iterations since initialize(), and the sub-steps that hit the cap.
  long contact_iterations() const { return contact_.contact_iterations(); }
  long unconverged_contact_steps() const { return contact_.unconverged_contact_steps(); }
  const StageContact& stage_contact() const { return contact_; }

 private:
  NohBatheCoefficients c_{};
  double dt_ = 0.0;
  // M, the stable step and the contact laws; the problems of the start and of each sub-step,
  // scales (pΔt)²/2, c₁ and c₂.
  StageContact contact_;
  StageProblem start_, first_, second_;
  State sub_;               // the state at t + pΔt
  Eigen::VectorXd u_next_;  // the displacement of the next sub-step point, fixed by the last
  Eigen::VectorXd scratch_;
};

using NohBatheExplicit = NohBatheScheme<ExplicitStageContact, SecondOrderSystem>;
using SparseNohBatheExplicit = NohBatheScheme<SparseExplicitStageContact, SparseSystem>;

}  // namespace impactid
