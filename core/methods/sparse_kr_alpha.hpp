// The KR-α explicit method (Kolay & Ricles 2014, doi:10.1002/eqe.2401; core/methods/kr_alpha.hpp)
// on a user's model of sparse matrices (core/model/sparse_system.hpp): the same update formulas,
// one template for both (core/methods/kr_alpha_recurrence.hpp: the model-based matrices applied
// through factorised M, D = M + γΔt·C + βΔt²·K and E = (1−α_m)·M + (1−α_f)·(γΔt·C + βΔt²·K), never
// formed; the velocity v̂ lagging the sample's by γΔt; the half-step energy), and the same contact
// conventions as core/methods/kr_alpha.hpp states them:
//   - Lagrange multipliers, as a forward increment: the multipliers λ_{n+1} >= 0 of the equilibrium
//     at t_{n+1}, taken whole, put the next displacement u_{n+2} on the walls where the
//     contact-free one would penetrate; so the constraints hold at every sample, and the multiplier
//     reported with the sample t_{n+1} is that of its own equilibrium, complementary to the gap at
//     t_{n+2}. The start's u₁ is fixed the same way by a multiplier in the start's equilibrium.
//   - the augmented Lagrangian: Uzawa's iterations on that problem with the springs' compliances,
//     counted; no snap.
//   - the penalty: the springs solved with that forward increment, (s·G·W + diag(1/k))·λ = g_next,
//     λ >= 0, complementary (core/methods/kr_alpha.hpp says why).
//
// Here M, C, K are sparse, M, D and E are factored once per run by
// core/model/sparse_factorization.hpp (M entry by entry when lumped), and the constraints are
// always a list. Their complementarity problem g_next − s·G·W·λ <= 0 (s = Δt²(½ + γ); W = E⁻¹·Gᵀ,
// the response of α1·a to the forces, core/methods/kr_alpha.hpp says why; at the start s = Δt²/2,
// W₀ = D⁻¹·Gᵀ) is formed once per run, one solve per constraint, and solved by Murty's pivoting
// with storage sized once (core/algebra/contact_lcp.hpp: any number of constraints). s·G·W is
// symmetric, its round-off averaged away. The responses W are not kept (dense for a 2D or 3D model,
// core/methods/sparse_integrators.hpp says why): when a force acts it moves the state by one solve
// with E with Gᵀ·λ as the right-hand side.
//
// Per step: two products with K (and C), one solve with E, two products with D, the reported
// acceleration's solve with M, O(n) vector work, the LCP, and when a force acts one more solve; no
// allocation once sized.
//
// Thread safety: one object per thread.
#pragma once

#include <string>

#include "core/algebra/contact_lcp.hpp"
#include "core/common/state.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/kr_alpha_recurrence.hpp"
#include "core/methods/method.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

class SparseKrAlphaExplicit {
 public:
  /// As KrAlphaExplicit::initialize: factors M, D and E and fixes the first displacement from
  /// `start` (a₀ consistent) with the contact at the start; start.a and start.multipliers then
  /// include that force. False, with failure() saying why, if a matrix is not positive definite
  /// (naming the DOF of the failed pivot) or `contact` is the penalty.
  bool initialize(const SparseSystem& system, const KrAlphaCoefficients& coefficients, double dt,
                  State& start, const ContactPenalties& contact = {});

  /// Advances state from t to t + Δt (u, v, a and the multipliers of the equilibrium at t + Δt).
  /// Returns true if a constraint pushes at t + Δt.
  bool step(const SparseSystem& system, State& state);

  /// KrAlphaExplicit::energy's half-step energy ½·wᵀM·w + ½·mᵀK·m, w = (u_next − u)/Δt,
  /// m = (u + u_next)/2, after step() returned `state`. Uses the scratch vectors: call it between
  /// steps.
  double energy(const SparseSystem& system, const State& state);

  /// Why initialize() failed; empty after a success.
  const std::string& failure() const { return failure_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }

 private:
  // One equilibrium's contact problem: the start's or the steps'.
  struct ContactProblem {
    bool start = false;
    double scale = 0.0;          // s: the next displacement moves by s·(α1·a)
    ConstraintListProblem list;  // s·G·W (and + diag(1/k) for the augmented Lagrangian)
  };
  // `a` holds a force vector f on entry, `w` gets the response of α1·a to it: the start's
  // w = D⁻¹·f (and a its acceleration's, M⁻¹·f), a step's w = E⁻¹·f (a unchanged: a step's
  // acceleration follows from w). No allocation once sized.
  void respond(bool start, Eigen::VectorXd& a, Eigen::VectorXd& w) const;
  void set_up(const SparseSystem& system, ContactProblem& problem);
  // The contact of an equilibrium: `next` holds the contact-free displacement of the next sample;
  // corrects recurrence_.w, next and, at the start, the acceleration `a` (null for a step) and
  // writes the multipliers into `at`. Returns true if a constraint pushes.
  bool enforce(const SparseSystem& system, const ContactProblem& problem, Eigen::VectorXd* a,
               Eigen::VectorXd& next, State& at);

  using Recurrence = KrAlphaRecurrence<SparseMatrix, SparseFactorization>;
  Recurrence recurrence_;  // KrAlphaExplicit's update formulas, on the sparse matrices
  ContactProblem start_problem_, step_problem_;
  Eigen::VectorXd forces_;
  Eigen::VectorXd response_a_, response_w_;  // a force's responses (respond())
  ContactLcpWorkspace lcp_;
  ContactPenalties contact_;
  ConstraintListLaw list_law_;
  std::string failure_;
};

}  // namespace impactid
