// The contact of an explicit stage, shared by the explicit multi-stage schemes on tridiagonal
// systems (Noh–Bathe, core/methods/noh_bathe.hpp; Kim's two-stage scheme,
// core/methods/kim_explicit.hpp): the factorised lumped (or consistent) mass, the stage's
// acceleration M·a = −K·u − C·ṽ, the stable step, and the forward-increment complementarity problem
// each stage solves for its multipliers, under the three contact laws of
// core/contact/contact_treatment.hpp.
//
// A stage's acceleration cannot change the displacement it is evaluated at, only the next one the
// scheme computes, linearly: next = (terms without a) + s·a, with the stage's scale s > 0. A
// contact force f in the stage's equilibrium (M·a = … − Gᵀ·f) then moves a by −M⁻¹·Gᵀ·f and the
// next displacement by −s·M⁻¹·Gᵀ·f. The laws:
// - **lagrange**: the forward increment (Carpenter, Taylor & Katona 1991,
//   doi:10.1002/nme.1620320107): the complementarity problem g_next − s·G·M⁻¹·Gᵀ·λ <= 0, λ >= 0,
//   complementary (one wall: one division; two walls: core/algebra/two_wall_contact.hpp; a list:
//   core/algebra/contact_lcp.hpp); the walls' dofs are snapped onto them where they push.
// - **penalty**: the explicit spring force λ = k·max(0, g(u_stage)) at the displacement u_stage
//   the stage's equilibrium is taken at, as central difference's at t
//   (core/methods/central_difference.hpp): no solve, no snap. The springs raise ω_max, so the
//   stable step shrinks with k: core/contact/stable_step.hpp's bound with the springs,
//   Ω_crit/ω_bound.
// - **augmented-lagrangian**: Uzawa's iterations (core/contact/contact_treatment.hpp) on the
//   penalised forward-increment problem, (s·G·M⁻¹·Gᵀ + diag(1/k))·λ = g_next + diag(1/k)·λ_j,
//   to the tolerance or the cap; counted. No snap.
//
// Per stage: O(n) vector work for the single wall and two walls, the constraints' columns for a
// list (their non-zero rows only); no allocation once initialize() and problem() have sized all.
//
// Thread safety: one object per thread.
#pragma once

#include <utility>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

/// One stage's forward-increment problem: its scale s and the constraint list's s·G·M⁻¹·Gᵀ, with
/// the springs' compliances on the diagonal for the penalty laws
/// (core/contact/constraint_list_law.hpp).
struct StageProblem {
  double scale = 0.0;
  ConstraintListProblem list;
};

/// The stable step of an explicit stage scheme: Ω_crit/ω_bound [s] with
/// core/contact/stable_step.hpp's bound ω_bound² on ω_max² (+inf for a mass that is not diagonal:
/// then 0, nothing certified; 0: +inf, no frequency), and whether Δt is within it (up to a relative
/// 1e-12).
struct StageStableStep {
  double step = 0.0;
  bool within = false;
};
StageStableStep stage_stable_step(double bound, double critical_omega, double dt);

class ExplicitStageContact {
 public:
  /// Factors M, computes the contact columns M⁻¹·Gᵀ, keeps the law, and the stable step
  /// Ω_crit/ω_bound with core/contact/stable_step.hpp's bound on ω_max, the penalty's springs
  /// included. False if M is singular.
  bool initialize(const SecondOrderSystem& system, const ContactPenalties& contact,
                  double critical_omega, double dt);
  /// The problem of a stage whose next displacement moves by `scale`·a. Allocates: set-up only.
  StageProblem problem(double scale) const;

  /// M·a = −K·u − C·v_predicted.
  void solve_acceleration(const SecondOrderSystem& system, const Eigen::VectorXd& u,
                          const Eigen::VectorXd& v_predicted, Eigen::VectorXd& a) const;

  /// The stage's contact forces under the law: `next` holds the contact-free next displacement,
  /// `at_u` the displacement of the stage's equilibrium (the penalty's). Corrects `a` and `next`
  /// by the forces, snaps the pushed walls' dofs (Lagrange), and keeps the forces as the last
  /// ones. Returns true if a constraint pushes.
  bool enforce(const SecondOrderSystem& system, const StageProblem& problem, Eigen::VectorXd& a,
               Eigen::VectorXd& next, const Eigen::VectorXd& at_u);
  /// x −= factor·M⁻¹·Gᵀ·(the last forces).
  void apply_last(const SecondOrderSystem& system, double factor, Eigen::VectorXd& x);
  /// Writes the last forces as `at`'s multipliers (lambda, far_lambda or multipliers).
  void write_last(const SecondOrderSystem& system, State& at) const;
  /// Adds the last forces to `at`'s multipliers.
  void add_last(const SecondOrderSystem& system, State& at) const;

  const TridiagonalFactorization& mass() const { return mass_; }
  /// The largest step certified stable without damping [s]: Ω_crit/ω_bound; 0 when none can be
  /// certified (a mass that is not diagonal).
  double stable_step() const { return stable_step_; }
  /// Whether Δt is within stable_step() (up to a relative 1e-12).
  bool within_stability_limit() const { return within_limit_; }
  const ContactPenalties& law() const { return contact_; }
  /// Augmented-Lagrangian iterations since initialize(), and the stage problems that hit the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }

 private:
  TridiagonalFactorization mass_;
  ContactPenalties contact_;
  double stable_step_ = 0.0;
  bool within_limit_ = false;
  Eigen::VectorXd contact_influence_;  // M⁻¹·e_c
  Eigen::VectorXd far_influence_;      // M⁻¹·e_far; empty without a far wall
  // The constraint list's columns M⁻¹·G_kᵀ, their non-zero rows, and G·M⁻¹·Gᵀ.
  Eigen::MatrixXd constraint_influence_;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> constraint_rows_;
  Eigen::MatrixXd delassus_;
  Eigen::VectorXd forces_, scaled_forces_;
  ConstraintListLaw list_law_;     // the list's law; counts every solve's Uzawa iterations
  double main_ = 0.0, far_ = 0.0;  // the last forces of the one- and two-wall contact
};

}  // namespace impactid
