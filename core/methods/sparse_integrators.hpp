// The integrators of core/methods/implicit_integrator.hpp and core/methods/central_difference.hpp
// on a sparse model (core/model/sparse_system.hpp): the same update formulas (written once:
// core/methods/implicit_update.hpp, core/methods/central_difference_recurrence.hpp; why the contact
// stays apart: core/methods/implicit_integrator.hpp), the same contact law
// (the constraints hold at the end of the step for the implicit family, at t + Δt for central
// difference's forward-increment multipliers, reported at t), with M, C and K sparse and the step's
// matrix factored by core/model/sparse_factorization.hpp once per run.
//
// Contact with several constraints at once: the columns A⁻¹·G_kᵀ are computed once per run (one
// solve each) to form the Delassus matrix D = s·G·A⁻¹·Gᵀ (m × m; s = b1·Δt² or 1), and kept only
// through it. Each step predicts the contact-free solution (one solve), computes the violations of
// every constraint, solves the complementarity problem LCP(−p, D) exactly with Murty's
// least-index principal pivoting (core/algebra/contact_lcp.hpp: it starts from the penetrating
// constraints, visits each active set at most once for a P-matrix, hence ends), and when a force
// acts corrects by one more solve with the forces Gᵀ·μ as right-hand side. Why a solve and not the
// stored columns: they are dense for a 2D or 3D model (n·m numbers, 64 MB per thread for 10⁵ DOFs
// and 80 contacts), where the solve costs O(nnz(L)) whatever m is. A step therefore costs one or
// two solves, O(nnz(L)), and allocates nothing.
//
// After every step, λ >= 0 holds by construction; the gaps hold to the solver's tolerance
// (kContactLcpTolerance of the largest violation), and complementarity holds exactly (a force is
// zero off the active set, the gap is closed on it: walls exactly, by snap_walls, pairs to
// round-off). The run's largest penetration is recorded (RunSummary::max_penetration).
//
// The implicit integrator takes the penalty and augmented-Lagrangian laws as the tridiagonal one
// does (core/contact/contact_treatment.hpp): the same problem with D + diag(1/(w·k)), and Uzawa's
// iterations on it, counted; walls are then not snapped (the penalty's node stands in the wall by
// λ/k). So does central difference, as on a tridiagonal system
// (core/methods/central_difference.hpp): the penalty's explicit force k·max(0, g(u_t)) at t, its
// stable step from core/contact/stable_step.hpp's bound on M⁻¹(K + springs) (reported, and a step
// above it flagged before the run), and Uzawa's iterations on the forward increment's penalty
// problem.
//
// Central difference takes Paoli–Schatzman's law as on a tridiagonal system: each gap shifted by
// −e·g_j(u₋) (core/methods/central_difference.hpp).
//
// Central difference needs a diagonal M (a lumped mass): initialize() refuses another with a
// message that says so. With stiffness-proportional or other non-diagonal damping the left-hand
// matrix M/Δt² + C/(2Δt) is factored like an implicit one.
//
// Thread safety: one object per thread.
#pragma once

#include <string>

#include "core/algebra/contact_lcp.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/central_difference_recurrence.hpp"
#include "core/methods/implicit_update.hpp"
#include "core/methods/method.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

class SparseImplicitIntegrator {
 public:
  /// Builds and factors the effective matrix. Returns false (with failure() saying why, naming
  /// the DOF of the failed pivot) when it is not positive definite.
  /// `contact`: the law of every constraint (resolve_contact of the model).
  bool initialize(const SparseSystem& system, const ImplicitCoefficients& coefficients, double dt,
                  const ContactPenalties& contact = {});
  /// Advances state from t to t + Δt (its acceleration consistent: consistent_acceleration).
  /// Returns true if a constraint is active at t + Δt.
  bool step(const SparseSystem& system, State& state);
  /// Shifts of the constraints' gaps, one per constraint, zero after initialize(): as
  /// ImplicitIntegrator::gap_offsets() (Wilson-θ's constraint at t + Δt).
  Eigen::VectorXd& gap_offsets() { return gap_offsets_; }
  const std::string& failure() const { return failure_; }
  const SparseFactorization& factorization() const { return factorization_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }

 private:
  ImplicitCoefficients c_{};
  double dt_ = 0.0;
  ContactPenalties contact_;
  SparseFactorization factorization_;
  ImplicitUpdate formulas_;  // u*, v* and the right-hand side, then the acceleration
  Eigen::VectorXd correction_;
  ConstraintListProblem list_;  // b1·Δt²·G·A⁻¹·Gᵀ (+ diag(1/(w·k)): penalty laws)
  ConstraintListLaw list_law_;
  Eigen::VectorXd forces_;
  Eigen::VectorXd gap_offsets_;  // gap_offsets()
  ContactLcpWorkspace lcp_;
  std::string failure_;
};

class SparseCentralDifference {
 public:
  /// Factors the left-hand matrix and starts from `initial` (Taylor start, as CentralDifference).
  /// Returns false with failure() when M is not diagonal or a pivot is not positive.
  /// `contact`: the law of every constraint (resolve_contact of the model), as
  /// CentralDifference's: Lagrange's forward increment, the explicit penalty force at t, or
  /// Uzawa's iterations on the forward increment's penalty problem.
  bool initialize(const SparseSystem& system, CdmVelocity velocity, double dt, const State& initial,
                  const ContactPenalties& contact = {});
  /// As CentralDifference::step: fills `at_t` with the state at the current t, moves to t + Δt.
  bool step(const SparseSystem& system, State& at_t);
  /// As CentralDifference::energy (core/methods/central_difference.hpp): the method's own energy at
  /// t + Δt/2 after a step() within the explicit limit, the plain one of `at_t` otherwise.
  double energy(const SparseSystem& system, const State& at_t);
  const std::string& failure() const { return failure_; }
  /// As CentralDifference's: whether Δt is within the explicit limit with the penalty's springs,
  /// and the largest step certified stable (2/ω_bound) [s].
  bool within_stability_limit() const { return within_limit_; }
  double stable_step() const { return stable_step_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }
  /// What initialize() and the steps so far set up, for the batched model kernel
  /// (core/batch/batched_model.hpp), which continues the recurrence lane by lane with these
  /// numbers: u₋, u and t, the left-hand matrix's factorisation, the Delassus matrix G·A⁻¹·Gᵀ.
  const CentralDifferenceRecurrence& recurrence() const { return recurrence_; }
  const SparseFactorization& factorization() const { return factorization_; }
  const ConstraintListProblem& contact_problem() const { return list_; }

 private:
  CentralDifferenceRecurrence recurrence_;  // the update formulas, u₋, u and u₊
  bool within_limit_ = false;
  double stable_step_ = 0.0;
  SparseFactorization factorization_;
  Eigen::VectorXd correction_;
  ConstraintListProblem list_;  // G·A⁻¹·Gᵀ (+ diag(1/k): penalty laws)
  Eigen::VectorXd forces_;
  Eigen::VectorXd gap_shifts_;  // Paoli–Schatzman's −e·g_j(u₋), as CentralDifference's
  ContactLcpWorkspace lcp_;
  ContactPenalties contact_;
  ConstraintListLaw list_law_;  // weight 1, as CentralDifference's
  std::string failure_;
};

/// a solving M·a = f − K·u − C·v − Gᵀ·λ (λ = state.multipliers, when set; f the load, if any): the
/// acceleration consistent with the equation of motion; NaN when M cannot be factored.
Eigen::VectorXd consistent_acceleration(const SparseSystem& system, const State& state);

}  // namespace impactid
