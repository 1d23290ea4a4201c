// The KR-α explicit method (Kolay & Ricles 2014, "Development of a family of unconditionally
// stable explicit direct integration algorithms with controllable numerical energy dissipation",
// Earthquake Engng Struct. Dyn. 43(9):1361–1380, doi:10.1002/eqe.2401; formulas, ρ∞ and the
// derived α_m, α_f, β, γ at KrAlphaParams, core/methods/method.hpp) on the tridiagonal systems (the
// rod, scenes of bodies, a model of tridiagonal matrices), with Lagrange-multiplier contact (or the
// penalty or the augmented Lagrangian, below).
//
// The model-based matrices α1 = D⁻¹·M, α2 = (½ + γ)·α1 and α3 = D⁻¹·N, with
//   D = M + γΔt·C + βΔt²·K,   N = α_m·M + α_f·γΔt·C + α_f·βΔt²·K,
// are dense, so they are never formed. Each is applied through the factorised tridiagonals M, D
// and E = D − N = (1−α_m)·M + (1−α_f)·(γΔt·C + βΔt²·K):
//   w = α1·a = D⁻¹·(M·a);
//   M·(I − α3)·a₁ = r − M·α3·a₀  ⇔  a₁ = a₀ + E⁻¹·D·(M⁻¹·r − a₀)   (M(I − α3) = M·D⁻¹·E),
// with r = −K·u_{1−α_f} − C·v_{1−α_f}. The stepper carries w, not a: applying α1 to the second
// line gives w₁ = w₀ + D⁻¹·M·E⁻¹·D·M⁻¹·(r − M·a₀), and D⁻¹·M·E⁻¹·D·M⁻¹ = E⁻¹ (D = M + B and
// E = (1 − α_m)·M + (1 − α_f)·B share B = γΔt·C + βΔt²·K, so M⁻¹·D and M⁻¹·E are functions of
// the one matrix M⁻¹·B and commute: D⁻¹·M·E⁻¹·D·M⁻¹ = (M⁻¹·D)⁻¹·(M⁻¹·E)⁻¹·(M⁻¹·D)·M⁻¹
// = (M⁻¹·E)⁻¹·M⁻¹ = E⁻¹), with M·a₀ = D·w₀:
//   w₁ = w₀ + E⁻¹·(r − D·w₀)                               (one product, one solve).
// A step is then two products with K (and C), one product with D and one solve with E, and O(n)
// vector work; the reported acceleration a₁ = M⁻¹·D·w₁ costs one more product and M's solve.
// D's factorisation is the start's (w₀ = D⁻¹·M·a₀). No allocation once sized.
//
// The velocity. Matching Taylor series in the update and the equilibrium shows that when u_n
// approximates u(t_n) to second order, the method's own velocity v̂_n (the v of the formulas at
// KrAlphaParams) approximates v(t_n − γΔt): started from the physical v₀ and reporting v̂_n, as
// the formulas read literally (and as OpenSees' KRAlphaExplicit does), both u and v converge only
// at first order (tests/kr_alpha_test.cpp measures it). So the stepper starts from
// v̂₀ = v₀ − γΔt·α1·a₀ and reports v_n = v̂_n + γΔt·α1·a_n; the step itself, v̂ in the damping
// term included, is the paper's, and both are then second order. The amplification matrix
// (core/spectral/amplification.cpp) is the map of the reported state, similar to that of (u, Δt·v̂,
// Δt²·a).
//
// Contact: a forward increment, as central difference's (Carpenter, Taylor & Katona 1991,
// core/methods/central_difference.hpp) and Noh–Bathe explicit's (core/methods/noh_bathe.hpp). The
// method is explicit in the displacement: u₁ = u₀ + Δt·v₀ + Δt²·(½ + γ)·α1·a₀ is fixed by the state
// at t, so the equilibrium at step n + 1 can no longer change u_{n+1}; the force it still chooses
// acts on u_{n+2} through a_{n+1}. The multipliers λ_{n+1} >= 0 are the contact forces in that
// equilibrium, taken whole (not α_f-weighted, as hht_contact = endpoint does for the α-methods:
// a weighted multiplier alternates during a persistent contact),
//   M·((I − α3)·a₁ + α3·a₀) + C·v_{1−α_f} + K·u_{1−α_f} + Gᵀ·λ₁ = 0,
// chosen so that the next displacement u_{n+2} lies on the wall where the contact-free one would
// penetrate: the complementarity problem g_next − s·G·W·λ <= 0, λ >= 0, complementary, with
// s = Δt²(½ + γ) and W = E⁻¹·Gᵀ the response of α1·a₁ to the force (the force enters r, and w₁
// moves by E⁻¹ times r's change, above; at the start W₀ = D⁻¹·Gᵀ): one wall, one division; two
// walls, core/algebra/two_wall_contact.hpp; a list, core/algebra/contact_lcp.hpp. The Delassus
// matrix s·G·E⁻¹·Gᵀ is symmetric positive definite for every symmetric M, C and K, whatever the
// damping (Rayleigh's, a scene's body by body, or a model's dashpot; tests/kr_alpha_test.cpp checks
// the identity with a dashpot); the solve that forms it leaves round-off, which
// symmetrize_contact_operator() averages away. The next displacement is computed once, there,
// snapped onto its wall, and used as such by the next step. So:
//   - the constraints hold at every sample t_{n+1} (enforced by λ_n);
//   - the multiplier reported with the sample t_{n+1} is that of its own equilibrium, λ_{n+1} >= 0,
//     complementary to the gap at t_{n+2} (as central difference's λ_t is to the gap at t + Δt).
// The first displacement u₁ = u₀ + Δt·v₀ + Δt²/2·α1·a₀ is fixed in initialize() the same way, by
// a multiplier in the equilibrium at the start, M·a₀ = −K·u₀ − C·v₀ − Gᵀ·λ₀ (response
// W₀ = D⁻¹·Gᵀ, scale Δt²/2), which then belongs to the start's acceleration.
//
// Penalty (core/contact/contact_treatment.hpp): the spring λ = k·max(0, g) of the displacement the
// equilibrium's force moves, u_{n+2}, solved with the forward increment: the problem above with the
// springs' compliances, (s·G·W + diag(1/k))·λ = g_next, λ >= 0, complementary (one wall:
// λ = p/(s·W_cc + 1/k)); the next displacement then penetrates by λ/k, the node is not snapped, and
// λ → Lagrange's at first order in 1/k. Why not the explicit spring of u_{n+1}, the displacement
// the equilibrium is taken at, as central difference's and the stage schemes' are: it acts outside
// the model-based matrices α1, α3 that make the method unconditionally stable, so its stable step
// is set by the springs through α's amplification, which core/contact/stable_step.hpp's Gershgorin
// bound does not give, and a run above it could not be flagged; putting the springs into α1, α3
// does not mend it (held closed, they freeze the contact node's response while open, and the energy
// grows; made to follow the contact state, the method goes unstable: docs/methods.md, "Decisions
// and findings"). Solved with the increment, the spring acts as the implicit methods' does with
// their step: the method stays unconditionally stable for every k
// (tests/contact_treatment_test.cpp, KrAlphaPenaltyIsTheSpringOfTheNextSampleAtAnyStep, runs
// k = 10⁴·K_cc at Courant 4).
//
// Augmented Lagrangian (core/contact/contact_treatment.hpp): Uzawa's iterations on the same
// problem, (s·G·W + diag(1/k))·λ = g_next + diag(1/k)·λ_j, from λ₀ = 0 (the penalty's solution) to
// the tolerance or the cap, counted in the run summary; the node is not snapped.
//
// A model of sparse matrices runs on core/methods/sparse_kr_alpha.hpp: the same formulas (one
// template, core/methods/kr_alpha_recurrence.hpp) and contact conventions, with M, D and E factored
// by core/model/sparse_factorization.hpp. The contact responses stay one class per system, for the
// reason core/methods/implicit_integrator.hpp gives: stored responses W = E⁻¹·Gᵀ on their non-zero
// rows here (and the named walls), one more solve with E there; different operations, whose bits
// the batched kernel (core/batch/kr_alpha_kernel.cpp) and the results files hold fixed.
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
#include "core/methods/kr_alpha_recurrence.hpp"
#include "core/methods/method.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

class KrAlphaExplicit {
 public:
  /// Factors M, D and E and fixes the first displacement u₁ = u₀ + Δt·v₀ + Δt²·α2·a₀ from
  /// `start` (a₀ consistent), with the contact at the start (the header): start.a and its
  /// multipliers (lambda, far_lambda or multipliers) then include that force. False, with
  /// failure() saying why, if a matrix is singular.
  /// `contact`: Lagrange's multipliers (default), the penalty or the augmented Lagrangian (the
  /// header).
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
  /// Ω = 8, in each period), so a stable run at a large Courant number was reported unstable. The
  /// displacements' principal roots are generalized-α's, which at ρ∞ = 1 are the trapezoidal
  /// rule's; for its displacement recurrence this half-step energy is the invariant, so at ρ∞ = 1
  /// it is conserved mode by mode (tests/kr_alpha_test.cpp,
  /// HalfStepEnergyIsConservedWithoutDissipation), and for ρ∞ < 1 it decays with the method's
  /// dissipation, after a bounded transient from the spurious root. Any growth of the displacements
  /// shows in it as in the plain one.
  /// Uses the scratch vectors: call it between steps.
  double energy(const SecondOrderSystem& system, const State& state);

  /// Why initialize() failed; empty after a success.
  const std::string& failure() const { return failure_; }
  /// Augmented-Lagrangian iterations since initialize(), and steps that ended at the cap.
  long contact_iterations() const { return list_law_.iterations(); }
  long unconverged_contact_steps() const { return list_law_.unconverged(); }

 private:
  // The response of the state to unit contact forces: of α1·a (`w`; the next displacement moves by
  // s·w) and, at the start only, of the acceleration (`a`; a step's follows from w). One set for
  // the start, one for the steps.
  struct ContactResponse {
    double scale = 0.0;              // s: the next displacement moves by s·w
    Eigen::VectorXd a_main, w_main;  // to the main wall's force
    Eigen::VectorXd a_far, w_far;    // to the far wall's; empty without a far wall
    Eigen::MatrixXd a_list, w_list;  // to each listed constraint's (columns)
    std::vector<std::pair<Eigen::Index, Eigen::Index>> rows_a, rows_w;  // their non-zero rows
    ConstraintListProblem list;  // s·G·W (and + diag(1/k) for the augmented Lagrangian)
  };
  // The response to the force vector f on each contact: the start's a = M⁻¹·f, w = D⁻¹·f, or a
  // step's w = E⁻¹·f (a left empty). Allocates: set-up only.
  void respond(bool start, const Eigen::VectorXd& force, Eigen::VectorXd& a,
               Eigen::VectorXd& w) const;
  void set_up(const SecondOrderSystem& system, bool start, ContactResponse& response);
  // The contact of an equilibrium: `next` holds the contact-free displacement of the next sample;
  // corrects recurrence_.w, next and, at the start, the acceleration `a` (null for a step, whose
  // acceleration follows from w) and writes the multipliers into `at`. Returns true if a
  // constraint pushes.
  bool enforce(const SecondOrderSystem& system, const ContactResponse& response, Eigen::VectorXd* a,
               Eigen::VectorXd& next, State& at);

  using Recurrence = KrAlphaRecurrence<Tridiagonal, TridiagonalFactorization>;
  Recurrence recurrence_;  // the update formulas, M, D, E and the state between samples
  ContactResponse start_response_, step_response_;
  Eigen::VectorXd forces_, scaled_forces_;
  ContactPenalties contact_;
  ConstraintListLaw list_law_;  // the list's law; counts every solve's Uzawa iterations
  std::string failure_;
};

/// KR-α's contact operator s·G·W of a constraint list (either system), made exactly symmetric
/// for the contact solver's Cholesky: g = (g + gᵀ)/2. It is symmetric in exact arithmetic for
/// every damping (the header), so what the average removes is the round-off of the solves that
/// formed it; an assertion checks that it is no more (a relative asymmetry of at most
/// 1e-6: round-off grows as the condition of D and E times ε, 1e-10 at a condition of 1e6; an
/// unsymmetric M, C or K reaching a stepper, which the scenes and the model reader never build,
/// shows as O(1)).
void symmetrize_contact_operator(Eigen::MatrixXd& g);

}  // namespace impactid
