// The KR-α explicit method (Kolay & Ricles 2014, "Development of a family of unconditionally
// stable explicit direct integration algorithms with controllable numerical energy dissipation",
// Earthquake Engng Struct. Dyn. 43(9):1361–1380, doi:10.1002/eqe.2401; formulas, ρ∞ and the
// derived α_m, α_f, β, γ at KrAlphaParams, core/method.hpp) on the tridiagonal systems (the rod,
// scenes of bodies, a model of tridiagonal matrices), with Lagrange-multiplier contact (or the
// augmented Lagrangian, below).
//
// The model-based matrices α1 = D⁻¹·M, α2 = (½ + γ)·α1 and α3 = D⁻¹·N, with
//   D = M + γΔt·C + βΔt²·K,   N = α_m·M + α_f·γΔt·C + α_f·βΔt²·K,
// are dense, so they are never formed. Each is applied through the factorised tridiagonals M, D
// and E = D − N = (1−α_m)·M + (1−α_f)·(γΔt·C + βΔt²·K):
//   w = α1·a = D⁻¹·(M·a)                                  (one product, one solve);
//   M·(I − α3)·a₁ = r − M·α3·a₀  ⇔  a₁ = a₀ + E⁻¹·D·(M⁻¹·r − a₀)   (M(I − α3) = M·D⁻¹·E),
// with r = −K·u_{1−α_f} − C·v_{1−α_f}. A step is then two products with K (and C), three
// solves (M, E, D), two products (D, M) and O(n) vector work: no allocation once sized.
//
// The velocity. Matching Taylor series in the update and the equilibrium shows that when u_n
// approximates u(t_n) to second order, the method's own velocity v̂_n (the v of the formulas at
// KrAlphaParams) approximates v(t_n − γΔt): started from the physical v₀ and reporting v̂_n, as
// the formulas read literally (and as OpenSees' KRAlphaExplicit does), both u and v converge only
// at first order (tests/kr_alpha_test.cpp measures it). So the stepper starts from
// v̂₀ = v₀ − γΔt·α1·a₀ and reports v_n = v̂_n + γΔt·α1·a_n; the step itself, v̂ in the damping
// term included, is the paper's, and both are then second order. The amplification matrix
// (core/amplification.cpp) is the map of the reported state, similar to that of (u, Δt·v̂, Δt²·a).
//
// Contact: a forward increment, as central difference's (Carpenter, Taylor & Katona 1991,
// core/central_difference.hpp) and Noh–Bathe explicit's (core/noh_bathe.hpp). The method is
// explicit in the displacement: u₁ = u₀ + Δt·v₀ + Δt²·(½ + γ)·α1·a₀ is fixed by the state at t,
// so the equilibrium at step n + 1 can no longer change u_{n+1}; the force it still chooses acts
// on u_{n+2} through a_{n+1}. The multipliers λ_{n+1} >= 0 are the contact forces in that
// equilibrium, taken whole (not α_f-weighted, as hht_contact = endpoint does for the α-methods:
// a weighted multiplier alternates during a persistent contact),
//   M·((I − α3)·a₁ + α3·a₀) + C·v_{1−α_f} + K·u_{1−α_f} + Gᵀ·λ₁ = 0,
// chosen so that the next displacement u_{n+2} lies on the wall where the contact-free one would
// penetrate: the complementarity problem g_next − s·G·W·λ <= 0, λ >= 0, complementary, with
// s = Δt²(½ + γ) and W = D⁻¹·M·E⁻¹·D·M⁻¹·Gᵀ the response of α1·a₁ to the force (one wall: one
// division; two walls: core/two_wall_contact.hpp; a list: core/contact_lcp.hpp). With damping
// proportional to M and K (the rod's Rayleigh damping; a scene's, body by body) W = E⁻¹·Gᵀ and
// the Delassus matrix s·G·W is symmetric positive definite; a list whose W is not symmetric
// (a model's damping of another form) is refused at initialize(). The next displacement is
// computed once, there, snapped onto its wall, and used as such by the next step. So:
//   - the constraints hold at every sample t_{n+1} (enforced by λ_n);
//   - the multiplier reported with the sample t_{n+1} is that of its own equilibrium, λ_{n+1} >= 0,
//     complementary to the gap at t_{n+2} (as central difference's λ_t is to the gap at t + Δt).
// The first displacement u₁ = u₀ + Δt·v₀ + Δt²/2·α1·a₀ is fixed in initialize() the same way, by
// a multiplier in the equilibrium at the start, M·a₀ = −K·u₀ − C·v₀ − Gᵀ·λ₀ (response
// W₀ = D⁻¹·Gᵀ, scale Δt²/2), which then belongs to the start's acceleration.
//
// Augmented Lagrangian (core/contact_treatment.hpp): Uzawa's iterations on the forward
// increment's problem above with the springs' compliances, (s·G·W + diag(1/k))·λ = g_next +
// diag(1/k)·λ_j, to the tolerance or the cap, counted in the run summary; the node is not snapped.
//
// A model of sparse matrices runs on core/sparse_kr_alpha.hpp: the same formulas and contact
// conventions, with M, D and E factored by core/sparse_factorization.hpp.
//
// Not offered (the run is refused with a message, core/simulation.cpp): penalty contact. An
// explicit penalty (the spring of the sample's penetration in its equilibrium, as the other
// explicit methods', core/explicit_stage_contact.hpp) acts outside the model-based matrices α1,
// α3 that make the method unconditionally stable: its stable step is then set by the springs
// through α's amplification, which core/stable_step.hpp's Gershgorin bound does not give, so a
// run above it could not be flagged. Putting the springs into α1, α3 does not mend it: held
// closed, they freeze the contact node's response while open (it drifts, the energy grows); made
// to follow the contact state, the method goes unstable (docs/methods.md, measured).
//
// Thread safety: one object per thread.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/contact_treatment.hpp"
#include "core/method.hpp"
#include "core/second_order_system.hpp"
#include "core/state.hpp"
#include "core/tridiagonal.hpp"

namespace impactid {

class KrAlphaExplicit {
 public:
  /// Factors M, D and E and fixes the first displacement u₁ = u₀ + Δt·v₀ + Δt²·α2·a₀ from
  /// `start` (a₀ consistent), with the contact at the start (the header): start.a and its
  /// multipliers (lambda, far_lambda or multipliers) then include that force. False, with
  /// failure() saying why, if a matrix is singular or a constraint list's contact operator is
  /// not symmetric.
  /// `contact`: Lagrange's multipliers (default) or the augmented Lagrangian (the header).
  bool initialize(const SecondOrderSystem& system, const KrAlphaCoefficients& coefficients,
                  double dt, State& start, const ContactPenalties& contact = {});

  /// Advances state from t to t + Δt (u, v, a and the multipliers of the equilibrium at t + Δt).
  /// Returns true if a constraint pushes at t + Δt.
  bool step(const SecondOrderSystem& system, State& state);

  /// The method's own energy after step() returned `state` (the sample t): the energy at the
  /// half step t + Δt/2 to the next displacement, which the last equilibrium fixed,
  ///   ½·wᵀM·w + ½·mᵀK·m,  w = (u_next − u)/Δt,  m = (u + u_next)/2.
  /// Why not ½vᵀMv + ½uᵀKu: past Ω = ωΔt ≈ 2 the sample's u and v of a mode are far from the
  /// ellipse that energy measures (a stable mode's plain energy swings by (1 + Ω²/4)², 289 at
  /// Ω = 8, in each period), so a stable run at a large Courant number was reported unstable.
  /// The displacements' principal roots are generalized-α's, which at ρ∞ = 1 are the trapezoidal
  /// rule's; for its displacement recurrence this half-step energy is the invariant, so at
  /// ρ∞ = 1 it is conserved mode by mode, and for ρ∞ < 1 it decays with the method's
  /// dissipation (after a transient from the spurious root of at most 1.45 times a mode's
  /// start, at Ω ≈ 2, ρ∞ = 0). Any growth of the displacements shows in it as in the plain one.
  /// Uses the scratch vectors: call it between steps.
  double energy(const SecondOrderSystem& system, const State& state);

  /// Why initialize() failed; empty after a success.
  const std::string& failure() const { return failure_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return iterations_; }
  long unconverged_contact_steps() const { return unconverged_; }

 private:
  // The response of the state to unit contact forces: of the acceleration (`a`) and of α1·a
  // (`w`; the next displacement moves by s·w). One set for the start, one for the steps.
  struct ContactResponse {
    Eigen::VectorXd a_main, w_main;  // to the main wall's force
    Eigen::VectorXd a_far, w_far;    // to the far wall's; empty without a far wall
    Eigen::MatrixXd a_list, w_list;  // to each listed constraint's (columns)
    std::vector<std::pair<Eigen::Index, Eigen::Index>> rows_a, rows_w;  // their non-zero rows
    Eigen::MatrixXd delassus;                                           // s·G·W
    Eigen::MatrixXd penalized;  // s·G·W + diag(1/k): augmented Lagrangian only
  };
  // The response to the force vector f on each contact: the start's a = M⁻¹·f, w = D⁻¹·f, or a
  // step's a = E⁻¹·D·M⁻¹·f, w = D⁻¹·M·a. Allocates: set-up only.
  void respond(const SecondOrderSystem& system, bool start, const Eigen::VectorXd& force,
               Eigen::VectorXd& a, Eigen::VectorXd& w) const;
  bool set_up(const SecondOrderSystem& system, bool start, ContactResponse& response);
  // The contact of the equilibrium whose acceleration is `a`: `next` holds the contact-free
  // displacement of the next sample; corrects a, w_ and next and writes the multipliers into
  // `at`. Returns true if a constraint pushes.
  bool enforce(const SecondOrderSystem& system, const ContactResponse& response, Eigen::VectorXd& a,
               Eigen::VectorXd& next, State& at);
  void count(const ContactIterations& iterations);

  KrAlphaCoefficients c_{};
  double dt_ = 0.0;
  double scale_ = 0.0;  // s = Δt²(½ + γ): the displacement's factor on w = α1·a
  Tridiagonal d_matrix_;
  TridiagonalFactorization mass_, d_, e_;
  ContactResponse start_response_, step_response_;
  Eigen::VectorXd violation_, forces_, scaled_forces_;
  Eigen::VectorXd w_;       // α1·a of the current sample (Δt·w is the next velocity increment)
  Eigen::VectorXd v_hat_;   // the method's velocity v̂, which lags the sample's by γΔt
  Eigen::VectorXd u_next_;  // the displacement of the next sample, fixed by the last equilibrium
  Eigen::VectorXd r_, y_;   // scratch
  // The augmented Lagrangian's springs' compliances 1/k and scratch (m).
  ContactPenalties contact_;
  Eigen::VectorXd compliance_, shift_, shifted_;
  long iterations_ = 0, unconverged_ = 0;
  std::string failure_;
};

}  // namespace impactid
