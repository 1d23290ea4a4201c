// The contact of an explicit stage on a user's sparse model (core/model/sparse_system.hpp), for the
// explicit multi-stage schemes (Noh–Bathe, core/methods/noh_bathe.hpp; Kim's two-stage scheme,
// core/methods/kim_explicit.hpp): what core/contact/explicit_stage_contact.hpp does on a
// tridiagonal system, by the same laws and conventions, with M sparse and the constraints always a
// list.
//
// M is factored once per run by core/model/sparse_factorization.hpp: entry by entry when it is
// diagonal (a lumped mass), by its sparse LDLᵀ when it is consistent. A stage's forward-increment
// problem is that of core/contact/explicit_stage_contact.hpp: g_next − s·G·M⁻¹·Gᵀ·λ <= 0, λ >= 0,
// complementary, with the Delassus matrix G·M⁻¹·Gᵀ formed once per run (one solve per constraint,
// core/contact/sparse_constraints.hpp) and solved by Murty's pivoting with storage sized once
// (core/algebra/contact_lcp.hpp: any number of constraints, as a block's bottom edge has). The
// columns M⁻¹·G_kᵀ are not kept (core/methods/sparse_integrators.hpp says why): when a force acts,
// M⁻¹·Gᵀ·λ is one more solve, kept for the stage's apply_last(). The laws:
// - **lagrange**: the forward increment; the pushed walls' DOFs are snapped onto them.
// - **penalty**: the explicit spring λ = k·max(0, g(u_stage)) at the displacement the stage's
//   equilibrium is taken at; the stable step Ω_crit/ω_bound uses core/contact/stable_step.hpp's
//   bound with the springs (0, nothing certified, for a mass that is not diagonal).
// - **augmented-lagrangian**: Uzawa's iterations on the penalised forward-increment problem,
//   (s·G·M⁻¹·Gᵀ + diag(1/k))·λ = g_next + diag(1/k)·λ_j, counted. No snap.
//
// Per stage: O(n) vector work, the LCP of the constraints, and one solve with M when a force acts
// (a division per DOF for a lumped mass); no allocation once initialize() and problem() have
// sized all.
//
// Thread safety: one object per thread.
#pragma once

#include <string>

#include "core/algebra/contact_lcp.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/contact/explicit_stage_contact.hpp"  // StageProblem
#include "core/model/sparse_factorization.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

class SparseExplicitStageContact {
 public:
  /// Factors M, forms G·M⁻¹·Gᵀ, keeps the law, and the stable step Ω_crit/ω_bound with
  /// core/contact/stable_step.hpp's bound on ω_max, the penalty's springs included. False, with
  /// failure() naming the DOF of the failed pivot, when M is not positive definite.
  bool initialize(const SparseSystem& system, const ContactPenalties& contact,
                  double critical_omega, double dt);
  /// The problem of a stage whose next displacement moves by `scale`·a. Allocates: set-up only.
  StageProblem problem(double scale) const;

  /// M·a = −K·u − C·v_predicted.
  void solve_acceleration(const SparseSystem& system, const Eigen::VectorXd& u,
                          const Eigen::VectorXd& v_predicted, Eigen::VectorXd& a) const;

  /// As ExplicitStageContact::enforce: the stage's forces under the law from the contact-free
  /// `next` (the penalty's from `at_u`); corrects `a` and `next`, snaps the pushed walls' DOFs
  /// (Lagrange), keeps the forces as the last ones. Returns true if a constraint pushes.
  bool enforce(const SparseSystem& system, const StageProblem& problem, Eigen::VectorXd& a,
               Eigen::VectorXd& next, const Eigen::VectorXd& at_u);
  /// x −= factor·M⁻¹·Gᵀ·(the last forces); no solve (enforce() kept M⁻¹·Gᵀ·λ).
  void apply_last(const SparseSystem& system, double factor, Eigen::VectorXd& x);
  /// Writes the last forces as `at`'s multipliers.
  void write_last(const SparseSystem& system, State& at) const;
  /// Adds the last forces to `at`'s multipliers.
  void add_last(const SparseSystem& system, State& at) const;

  /// Why initialize() failed; empty after a success.
  const std::string& failure() const { return failure_; }
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
  SparseFactorization mass_;
  ContactPenalties contact_;
  double stable_step_ = 0.0;
  bool within_limit_ = false;
  Eigen::MatrixXd delassus_;         // G·M⁻¹·Gᵀ
  Eigen::VectorXd last_correction_;  // M⁻¹·Gᵀ·(the last forces)
  Eigen::VectorXd forces_;
  ConstraintListLaw list_law_;
  ContactLcpWorkspace lcp_;
  std::string failure_;
};

}  // namespace impactid
