// Kim's two-stage explicit scheme (W. Kim, "An accurate two-stage explicit time integration scheme
// for structural dynamics and various dynamic problems", Int. J. Numer. Methods Eng. 120 (2019)
// 1–28, doi:10.1002/nme.6098; formulas, range of p and stability limit at KimExplicitParams,
// core/methods/method.hpp) on the tridiagonal systems (the rod, scenes of bodies, a model of
// tridiagonal matrices: KimExplicit) and on a user's model of sparse matrices
// (core/model/sparse_system.hpp: SparseKimExplicit), with the three contact laws of
// core/contact/contact_treatment.hpp. Both are one template over the stage contact
// (core/contact/explicit_stage_contact.hpp, core/contact/sparse_explicit_stage_contact.hpp), so
// they step by the same formulas and contact conventions; on a sparse model the constraints are
// always a list, M is factored once per run by core/model/sparse_factorization.hpp (entry by entry
// when lumped), and a stage's force acts through one more solve with M instead of stored columns.
// This is not ref. 17 of Serfőző & Pere 2022 (Kim, Engineering Structures 195 (2019) 358–372,
// parameter ρ_b): that scheme's formulas were not available to us; this one is the same author's
// scheme of the same year, as Kratos implements it.
//
// The previous step's acceleration: the step starts from (u₀, v₀, a₀) with a₀ the acceleration the
// last step computed at its predicted ũ₁ (with that stage's contact force), not the equilibrium
// acceleration at u₀. The first step takes the start's consistent acceleration (M·a₀ = −K·u₀ −
// C·v₀, the start's contact force included, as every method here starts). After a contact event
// nothing is reset: the multiplier a stage finds belongs to that stage's acceleration, which the
// scheme's own formulas carry forward, so a₀ holds the force that acted at the end of the previous
// step (restarting from the equilibrium at u₁ would make the step a different scheme).
//
// Contact (Lagrange multipliers, the default): a forward increment at each stage, as central
// difference's (Carpenter, Taylor & Katona 1991, core/methods/central_difference.hpp) and
// Noh–Bathe's (core/methods/noh_bathe.hpp). A stage's acceleration cannot change the displacement
// it is evaluated at, only later ones, linearly:
//   stage 1 (equilibrium at t + pΔt, at u_p): ũ₁ = (terms without a_p) + s₁·a_p, s₁ = Δt²/(6p);
//     its multipliers λ_p put the predicted ũ₁, where stage 2 evaluates the forces, on the walls;
//   stage 2 (equilibrium at t + Δt, at ũ₁): u₁ = (…) + s_u·a₁, s_u = (1 − 2p)·Δt²/(12(1 − p)), and
//     the next step's u_p = u₁ + pΔt·v₁ + (pΔt)²/2·a₁ = (…) + s_n·a₁,
//     s_n = (1 + 2p − 6p³)·Δt²/(12(1 − p)) (> 0 on [⅓, ½]); its multipliers λ₁ are the sum of
//     those that put the sample u₁ on the walls (skipped at p = ½, where s_u = 0 and u₁ = ũ₁ is
//     already admissible) and the further ones, >= 0, that put the next u_p there too.
// Each is the complementarity problem g − s·G·M⁻¹·Gᵀ·λ <= 0, λ >= 0, complementary (one wall: a
// division; two walls: core/algebra/two_wall_contact.hpp; a list: core/algebra/contact_lcp.hpp).
// So:
//   - the constraints hold at every displacement the scheme computes: each sample t + Δt (by
//     λ₁ and λ_p), each force point t + pΔt (by the previous λ₁) and each predicted ũ₁ (by λ_p);
//   - the multiplier reported with the sample t + Δt is λ₁ >= 0, the force in the equilibrium the
//     scheme evaluates at t + Δt (at ũ₁), the one that also acts on the next step through a₀;
//     complementary to the gap at u₁ where that binds, else to the gap at the next u_p. The
//     stage's λ_p (substep_state()) is complementary to the gap at ũ₁.
// Why both at stage 2: the sample is what a user reads (and what the Signorini check tests), and
// the next force point is where the following stage starts (as for Noh–Bathe, neither stage then
// starts from a penetrating state); one multiplier per constraint can meet both because each
// pushes both away from the wall (s_u >= 0, s_n > 0 on [⅓, ½]; above ½ s_u < 0, one reason
// KimExplicitParams refuses those p). The start's u_p is fixed in initialize() the same way, by a
// multiplier at the start (coefficient (pΔt)²/2), which then belongs to the start's acceleration.
//
// Penalty: at each stage the explicit spring force λ = k·max(0, g) of the displacement its
// equilibrium is taken at: λ_p of u_p, λ₁ of ũ₁ (at p = ½ the sample u₁ itself; otherwise u₁
// differs from ũ₁ by s_u·Δa, and the sample's penetration from the spring's by as much), as
// central difference's at t. Nothing is solved for the next force point. The springs raise
// ω_max: the stable step Ω_crit(p)/ω_bound uses core/contact/stable_step.hpp's bound with them, and
// a step above it is flagged before the run starts. Augmented Lagrangian: Uzawa's iterations on
// each of the forward-increment problems above (stage 1, the sample, the next force point) with
// the springs' compliances (core/contact/explicit_stage_contact.hpp), counted in the run summary.
// Neither snaps a node onto its wall.
//
// Per step: two solves with the factorised M (diagonal for a lumped mass), two products with K
// (and with C when damped), O(n) vector work (on a sparse model, O(nnz) products, and one more
// solve per stage problem whose contact pushes), no allocation once sized (initialize sizes all).
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
class KimScheme {
 public:
  /// Factors M and fixes the first stage's displacement u_p = u₀ + pΔt·v₀ + (pΔt)²/2·a₀ from
  /// `start` (a₀ consistent), with the contact at the start (the header): start.a and its
  /// multipliers (lambda, far_lambda or multipliers) then include that force. False if M is
  /// singular (on a sparse model not positive definite: stage_contact().failure() says where).
  /// `contact` says how the constraints are enforced (the header; default Lagrange).
  bool initialize(const System& system, const KimExplicitCoefficients& coefficients, double dt,
                  State& start, const ContactPenalties& contact = {});

  /// Advances state from t to t + Δt: u₁, v₁, the acceleration a₁ of the second stage (at ũ₁) and
  /// its multipliers λ₁. Returns true if a constraint pushes at t + Δt.
  bool step(const System& system, State& state);

  /// The first stage of the last step: u_p, the predicted v₀ + pΔt·a₀, a_p, λ_p, t + pΔt.
  const State& substep_state() const { return sub_; }
  /// The largest step certified stable without damping: Ω_crit(p)/ω_bound with
  /// core/contact/stable_step.hpp's Gershgorin bound ω_bound on ω_max [s]; 0 when none can be
  /// certified (a mass that is not diagonal).
  double stable_step() const { return contact_.stable_step(); }
  /// Whether Δt is within stable_step() (up to a relative 1e-12).
  bool within_stability_limit() const { return contact_.within_stability_limit(); }
  /// Augmented-Lagrangian iterations since initialize(), and the stage problems that hit the cap.
  long contact_iterations() const { return contact_.contact_iterations(); }
  long unconverged_contact_steps() const { return contact_.unconverged_contact_steps(); }
  const StageContact& stage_contact() const { return contact_; }

 private:
  static void clear_multipliers(State& at);
  // D at dof i from a₀ (a0_), a_p (sub_.a) and a₁ (state.a).
  double divided_difference(Eigen::Index i, const State& state) const;
  // u₁ = ũ₁ + cu·Δt²·D and v₁ = ṽ₁ + cv·Δt·D; correct_velocity() the latter only (after a
  // multiplier changed a₁: u₁ then has its correction and its snap already).
  void correct(State& state) const;
  void correct_velocity(State& state) const;

  KimExplicitCoefficients c_{};
  double dt_ = 0.0;
  // M, the stable step and the contact laws; the problems of the start, of stage 1, of the
  // sample and of the next force point, scales (pΔt)²/2, s₁, s_u and s_n.
  StageContact contact_;
  StageProblem start_, first_, sample_, next_;
  State sub_;                                  // the first stage: at t + pΔt
  Eigen::VectorXd a0_;                         // a₀ of the step
  Eigen::VectorXd u_predicted_, v_predicted_;  // ũ₁, ṽ₁
  Eigen::VectorXd u_next_;                     // u_p of the next step, fixed by the last stage
};

using KimExplicit = KimScheme<ExplicitStageContact, SecondOrderSystem>;
using SparseKimExplicit = KimScheme<SparseExplicitStageContact, SparseSystem>;

}  // namespace impactid
