// The time-stepping methods and their parameters, in the paper's conventions
// (Serfőző & Pere 2022, sec. 2, doi:10.1556/606.2022.00599).
//
// Converting from other tools: MFEM's and OpenSees' HHT "alpha" is 1 + our α (they use
// α ∈ [2/3, 1]); OpenSees orders Newmark as (γ, β), MFEM as (β, γ); Chung & Hulbert's α_f is
// our −α for HHT. Generalized-α follows Chung & Hulbert (1993), doi:10.1115/1.2900803.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <variant>

#include "core/common/parameter_error.hpp"

namespace impactid {

enum class MethodKind {
  central_difference,
  backward_euler,
  newmark,
  hht,
  generalized_alpha,
  bathe,
  rho_bathe,
  tr_bdf2,
  houbolt,
  wilson_theta,
  noh_bathe,
  kim_explicit,
  kr_alpha,
  /// The first kind register_method() hands out; each registration takes the next.
  first_registered
};
/// "cdm", "backward-euler", "newmark", "hht", "generalized-alpha", …: the names used alike on the
/// command line, in plan files and in HDF5 attributes (core/methods/method_registry.hpp holds
/// them).
const char* to_string(MethodKind kind);
std::optional<MethodKind> method_kind_from_string(const std::string& name);

/// How central difference reports (and, with damping, uses) the velocity.
enum class CdmVelocity {
  central,   ///< eq. 3: v_t = (u_{t+Δt} − u_{t−Δt})/(2Δt); damping by eq. 5
  backward,  ///< eq. 6: v_t = (u_t − u_{t−Δt})/Δt; damping by eq. 7 (explicit with lumped M)
};
const char* to_string(CdmVelocity kind);
std::optional<CdmVelocity> cdm_velocity_from_string(const std::string& name);

/// Where the contact force of an α-method acts within the step.
enum class ContactWeighting {
  /// G^T·λ_{t+Δt}, unweighted: the default, because the multiplier then is the contact force
  /// at t+Δt itself. Weighted like the elastic forces, the multiplier satisfies
  /// (1−α_f)·λ_{t+Δt} + α_f·λ_t = const during a persistent contact, so for α_f → 0.5 it
  /// alternates from step to step without damping.
  endpoint,
  /// G^T·((1−α_f)·λ_{t+Δt} + α_f·λ_t), consistent with the α-weighting of eq. 14.
  weighted,
};
const char* to_string(ContactWeighting kind);
std::optional<ContactWeighting> contact_weighting_from_string(const std::string& name);

/// Central difference with Carpenter's forward-increment Lagrange multiplier
/// (Carpenter, Taylor & Katona 1991, doi:10.1002/nme.1620320107). Explicit with a lumped mass;
/// stable for Courant numbers below 1 (lumped mass, no damping; see central_difference.hpp).
struct CentralDifferenceParams {
  CdmVelocity velocity = CdmVelocity::central;
};

/// Backward Euler, eqs 8–10: first order, unconditionally stable, strongly dissipative.
struct BackwardEulerParams {};

struct BetaGamma {
  double beta;   ///< > 0
  double gamma;  ///< >= 0; < 1/2 is unstable
};

/// Newmark, eqs 11–12, in the δ form of eq. 13 (β = (1+δ)²/4, γ = 1/2 + δ) unless explicit
/// coefficients are given. δ = 0 is the trapezoidal rule (average acceleration); δ = 1 gives
/// the same displacements and contact forces as backward Euler.
/// Default δ = 0.3: the low end of the paper's practical range δ ∈ [0.3, 1] (sec. 4.1), where ε_p
/// is smallest on the default scene. With Lagrange contact the trapezoidal rule (δ = 0) chatters on
/// the wall: it spreads each impulse of λ over two steps, so every release injects energy, and at
/// small δ the chatter comes and goes with δ (docs/methods.md, "Decisions and findings").
struct NewmarkParams {
  double delta = 0.3;                     ///< δ >= 0 (eq. 13)
  std::optional<BetaGamma> coefficients;  ///< when set, replaces eq. 13
};

/// HHT-α, eq. 14, with β and γ from eq. 13. α ∈ [−0.5, 0]; δ defaults to −α, which is exactly
/// the second-order choice of eq. 15. δ < −α is unstable (for every Δt: ξ̄ ≈ (α+δ)/2·Ω < 0).
/// The high-frequency damping is ρ∞ = (1+α)/(1−α) only for α ∈ [−1/3, 0]; below −1/3 a spurious
/// root dominates, ρ∞ = −α/(1+α), which reaches 1 at α = −0.5: no high-frequency damping at
/// the paper's end of the range, whatever δ. δ = −1.5α (eq. 19) minimises the period error as
/// Ω → 0 (core/spectral/amplification.hpp), at the price of first order.
struct HhtParams {
  double alpha = -0.3;          ///< α ∈ [−0.5, 0]
  std::optional<double> delta;  ///< δ >= 0; default −α
  ContactWeighting contact = ContactWeighting::endpoint;
};

/// Generalized-α (Chung & Hulbert 1993) parametrised by the high-frequency spectral radius.
struct GeneralizedAlphaParams {
  double rho_inf = 0.8;  ///< ρ∞ ∈ [0, 1]; 1 is the trapezoidal rule
  ContactWeighting contact = ContactWeighting::endpoint;
};

/// The original Bathe composite scheme (Bathe & Baig 2005, doi:10.1016/j.compstruc.2005.08.001;
/// Bathe 2007, doi:10.1016/j.compstruc.2006.09.004): a trapezoidal sub-step to t + Δt/2, then
/// the 3-point backward Euler formula over t, t + Δt/2, t + Δt. Second order, ρ∞ = 0. It is
/// ρ∞-Bathe with ρ∞ = 0 and γ = 1/2 (core/methods/bathe_composite.hpp steps both).
struct BatheParams {};

/// The ρ∞-Bathe composite scheme (Noh & Bathe 2019, doi:10.1016/j.compstruc.2018.11.001): a
/// trapezoidal sub-step to t + γ·Δt, then
///   v₁ = v₀ + Δt·(q0·a₀ + q1·a_γ + q2·a₁),   u₁ = u₀ + Δt·(q0·v₀ + q1·v_γ + q2·v₁),
/// with q1 = (ρ∞ + 1)/(2γ(ρ∞ − 1) + 4), q2 = ½ − γ·q1, q0 = 1 − q1 − q2: second order for every
/// γ ∈ (0, 1), with the high-frequency spectral radius ρ∞.
/// Default γ: γ₀ = (2 − √(2 + 2ρ∞))/(1 − ρ∞) (½ at ρ∞ = 1), where q2 = γ/2 and both sub-steps
/// have the same effective matrix, the value the paper recommends; ρ∞ = 0 then gives
/// γ = 2 − √2, TR-BDF2's. ρ∞ = 1 with γ = ½ is the trapezoidal rule applied twice with Δt/2.
struct RhoBatheParams {
  double rho_inf = 0.0;         ///< ρ∞ ∈ [0, 1]
  std::optional<double> gamma;  ///< sub-step ratio γ ∈ (0, 1); default γ₀(ρ∞)
};

/// TR-BDF2 (Bank, Coughran, Fichtner, Grosse, Rose & Smith 1985, doi:10.1109/T-ED.1985.22232),
/// the γ = 2 − √2 variant: a trapezoidal sub-step to t + γΔt, then BDF2 over t, t + γΔt, t + Δt,
/// applied to u̇ = v and v̇ = a. Second order, L-stable (ρ∞ = 0). It is ρ∞-Bathe with ρ∞ = 0 and
/// γ = 2 − √2 (with ρ∞ = 0, q0 = q1 for every γ, which turns the three-point formula into
/// BDF2 through the trapezoidal relation v₀ + v_γ = 2(u_γ − u₀)/(γΔt)), and so ρ∞-Bathe's
/// default; stepped by the same code (core/methods/bathe_composite.hpp).
struct TrBdf2Params {};

/// Houbolt's method (Houbolt 1950, J. Aeronaut. Sci. 17(9):540–550, doi:10.2514/8.1722): the
/// cubic through u_{n−2}, u_{n−1}, u_n, u_{n+1} differentiated at t_{n+1},
///   a_{n+1} = (2u_{n+1} − 5u_n + 4u_{n−1} − u_{n−2})/Δt²,
///   v_{n+1} = (11u_{n+1} − 18u_n + 9u_{n−1} − 2u_{n−2})/(6Δt),
/// with equilibrium (and the contact) at t_{n+1}. A three-step method: implicit, second order,
/// unconditionally stable, ρ∞ = 0, and dissipative at every Ω (ξ̄ ≈ Ω³/2; period error
/// 11/24·Ω²). No parameter. Its start-up and its steps as members of the one-step family:
/// core/methods/houbolt.hpp.
struct HouboltParams {};

/// θ of Wilson-θ below which it is not unconditionally stable: (1 + √3)/2 = 1.3660…, the root of
/// 2θ² − 2θ − 1 = 0 at which the limit Ω → ∞ of its amplification matrix has the eigenvalue −1
/// (the usual "θ >= 1.37" rounds it up; tests/wilson_theta_test.cpp measures both sides).
inline constexpr double kWilsonThetaMinimum = 1.3660254037844386;

/// Wilson-θ (Wilson, Farhoomand & Bathe 1972, Earthquake Eng. Struct. Dyn. 1:241–252,
/// doi:10.1002/eqe.4290010305): equilibrium at t + θΔt with the linear-acceleration step
/// (Newmark β = 1/6, γ = ½) of length θΔt, then back to t + Δt along the same linear
/// acceleration:
///   a_{n+1} = a_n + (a_θ − a_n)/θ,  v_{n+1} = v_n + Δt(a_n + a_{n+1})/2,
///   u_{n+1} = u_n + Δt·v_n + Δt²(2a_n + a_{n+1})/6.
/// Implicit, second order (period error (6θ² − 6θ + 1)/24·Ω², ξ̄ ≈ θ(θ−1)(2θ−1)/12·Ω³), stable for
/// every Δt exactly when θ >= (1 + √3)/2 (kWilsonThetaMinimum; tests/wilson_theta_test.cpp checks θ
/// up to 3). ρ∞ at the default θ = 1.4 is 0.7784 (a real root: the high frequencies alternate in
/// sign), not monotone in θ (0.53 at 1.5, 0.63 at 2). Where the contact holds and which multiplier
/// is reported: core/methods/wilson_theta.hpp.
struct WilsonThetaParams {
  double theta = 1.4;  ///< θ >= (1 + √3)/2 and finite; 1.4, the value in common use
};

/// The Noh–Bathe explicit scheme (Noh & Bathe 2013, "An explicit time integration scheme for the
/// analysis of wave propagations", Computers & Structures 129:178–193,
/// doi:10.1016/j.compstruc.2013.06.007): two explicit sub-steps per step, t → t + pΔt → t + Δt,
///   u_p = u₀ + pΔt·v₀ + (pΔt)²/2·a₀,             M·a_p = −K·u_p − C·(v₀ + pΔt·a₀),
///   v_p = v₀ + pΔt/2·(a₀ + a_p),
///   u₁ = u_p + (1−p)Δt·v_p + ((1−p)Δt)²/2·a_p,    M·a₁ = −K·u₁ − C·(v_p + (1−p)Δt·a_p),
///   v₁ = v_p + (1−p)Δt·(q0·a₀ + (½ + q1)·a_p + q2·a₁),
/// q1 = (1 − 2p)/(2p(1 − p)), q2 = ½ − p·q1, q0 = −q1 − q2 + ½ (the weights sum to 1, and q2 makes
/// the velocity exact for a linear acceleration: second order). Without the ½ on a_p, as the
/// formula is often quoted, the weights sum to ½ and the scheme is inconsistent.
/// Undamped (ü + ω²u = 0, Ω = ωΔt) its amplification matrix has
///   det = 1 − (1−p)²(2p−1)·Ω⁴/4,   trace = 2 − Ω² + p²(1−p)·Ω⁴/2,
/// so p < ½ makes det > 1 for every Ω > 0: unconditionally unstable (negative dissipation,
/// ρ ≈ 1 + (1−p)²(1−2p)Ω⁴/8), although the paper's family is written for p ∈ (0, 1). p = ½ is two
/// velocity-Verlet (central difference) half steps: no dissipation, Ω_crit = 4. Hence the range
/// [½, 1). Period error −(3p − 2)²/24·Ω², damping ratio ξ̄ ≈ (1−p)²(2p−1)/8·Ω³: second order.
/// The stability limit Ω_crit(p) is noh_bathe_critical_omega(); 3.7450 at the default p = 0.54,
/// where an eigenvalue leaves the unit circle through +1. Explicit: needs a factorisation of M
/// only (diagonal for a lumped mass), two solves per step. Contact: core/methods/noh_bathe.hpp.
struct NohBatheParams {
  double p = 0.54;  ///< sub-step ratio p ∈ [½, 1); 0.54, the paper's recommended value
};

/// Kim's two-stage explicit scheme (W. Kim, "An accurate two-stage explicit time integration
/// scheme for structural dynamics and various dynamic problems", International Journal for
/// Numerical Methods in Engineering 120 (2019) 1–28, doi:10.1002/nme.6098), as implemented in
/// Kratos (StructuralMechanicsApplication, explicit_multi_stage_kim_scheme.hpp, whose parameter
/// `fraction_delta_time` is our p). It is not ref. 17 of Serfőző & Pere 2022 (Kim, Engineering
/// Structures 195 (2019) 358–372, parameter ρ_b), whose formulas were not available to us.
/// Two explicit stages per step, at t + pΔt and t + Δt, then a correction of the end values:
///   u_p = u₀ + pΔt·v₀ + (pΔt)²/2·a₀,               M·a_p = −K·u_p − C·(v₀ + pΔt·a₀),
///   ũ₁ = u₀ + Δt·v₀ + Δt²/2·((1 − 1/(3p))·a₀ + a_p/(3p)),
///   ṽ₁ = v₀ + Δt·((1 − 1/(2p))·a₀ + a_p/(2p)),     M·a₁ = −K·ũ₁ − C·ṽ₁,
///   D = a₀/p − a_p/(p(1 − p)) + a₁/(1 − p)   (a's second divided difference on 0, p, 1),
///   u₁ = ũ₁ + (1 − 2p)·Δt²/12·D,   v₁ = ṽ₁ + (2 − 3p)·Δt/6·D.
/// The end values integrate the quadratic through a₀, a_p, a₁ exactly (Simpson's rule at p = ½);
/// the step keeps a₁, the acceleration at the predicted ũ₁, as the next step's a₀ rather than
/// evaluating the forces a third time at u₁: two force evaluations per step, and a state
/// (u, v, a) whose a is not the equilibrium acceleration at u (a one-step map with memory; the
/// first step takes the consistent a₀ of the start, core/methods/kim_explicit.hpp).
/// Undamped (Ω = ωΔt) its 3×3 amplification matrix (core/spectral/amplification.cpp) has the
/// spurious root 0 at Ω → 0 and the principal pair's period error c₄(p)·Ω⁴: no Ω² term at any p (c₄
/// = 1/720 at p = ⅓, 0 at p = 5/12, −1/480 at p = ½), and damping ratio ξ̄ ≈ (3p − 1)/(144(1 −
/// p))·Ω³, none to that order at p = ⅓ (where ρ(1) = 0.99968, ρ(2) = 0.9516). Second order (step
/// halving). Range p ∈ [⅓, ½]: below ⅓ the principal pair grows for small Ω (ρ > 1 from Ω ≈ 0.01),
/// unstable at every useful step. Above ½ it is stable, but (i) its limit falls below √6 (1.89 at
/// p = ⅔, below central difference's 2 from p ≈ 0.62, at twice its cost per step) and (ii) the
/// correction moves u₁ towards a wall when a₁'s contact force pushes away from it (the weight of
/// a₁ in u₁, (1 − 2p)/(12(1 − p))·Δt², turns negative), so no multiplier at the second stage can
/// keep the sample admissible: those p are refused. The stability limit Ω_crit(p)
/// (kim_explicit_critical_omega()) is √6 at both ends and 3.0815 at p = 0.4418.
/// Default p = ½, not Kratos' ⅓: at p = ½ the correction leaves the displacement alone (u₁ = ũ₁),
/// so the contact's forward increment acts on the sample directly. On the paper's rod small p
/// chatters: the quadratic correction turns the first stage's contact impulse into an overshoot
/// that the second stage must pull back, so that the contact opens and closes again and again,
/// while p = ½ does not (REPRODUCTION.md has the sweep). p = 5/12 has the least period error
/// (no Ω⁴ term).
struct KimExplicitParams {
  double p = 0.5;  ///< stage ratio p ∈ [⅓, ½]; ½ (see above; Kratos' default is ⅓)
};

/// The KR-α explicit method (Kolay & Ricles 2014, "Development of a family of unconditionally
/// stable explicit direct integration algorithms with controllable numerical energy
/// dissipation", Earthquake Engng Struct. Dyn. 43(9):1361–1380, doi:10.1002/eqe.2401): explicit
/// displacement and velocity, from the state at t alone,
///   v₁ = v₀ + Δt·α1·a₀,   u₁ = u₀ + Δt·v₀ + Δt²·α2·a₀,
/// then the generalized-α equilibrium at t + (1−α_f)Δt with the matrix α3 in α_m's place,
///   M·((I − α3)·a₁ + α3·a₀) + C·((1−α_f)·v₁ + α_f·v₀) + K·((1−α_f)·u₁ + α_f·u₀) = F,
/// the model-based matrices (D = M + γΔt·C + βΔt²·K)
///   α1 = D⁻¹·M,   α2 = (½ + γ)·α1,   α3 = D⁻¹·(α_m·M + α_f·γΔt·C + α_f·βΔt²·K),
/// and Chung & Hulbert's scalars from ρ∞: α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1),
/// γ = ½ − α_m + α_f, β = ¼(1 − α_m + α_f)² (kr_alpha_coefficients). OpenSees'
/// KRAlphaExplicit writes the same scheme with α_m, α_f replaced by 1 − α_m, 1 − α_f.
/// For a linear system its amplification matrix has the characteristic polynomial of
/// generalized-α with the same ρ∞ (tests/kr_alpha_test.cpp checks it): unconditionally stable,
/// second order (period error (11ρ∞² − 14ρ∞ + 11)/(24(1 + ρ∞)²)·Ω²), ρ → ρ∞ as Ω → ∞, and
/// non-dissipative at ρ∞ = 1 (then the trapezoidal rule's spectrum). The matrices are never
/// formed: each step applies them through tridiagonal solves (core/methods/kr_alpha.hpp), O(n). The
/// v of these formulas lags u by γΔt: the stepper starts it from v₀ − γΔt·α1·a₀ and reports v +
/// γΔt·α1·a (core/methods/kr_alpha.hpp says why; read literally the scheme is first order). Default
/// ρ∞ = 0.8: generalized-α's default here (the same spectrum, so the same trade-off: ρ(Ω = 1) stays
/// above 0.99 while the highest rod modes are damped towards 0.8 per step).
struct KrAlphaParams {
  double rho_inf = 0.8;  ///< ρ∞ ∈ [0, 1]
};

/// The parameters of a method registered from outside the library (register_method(),
/// core/methods/method_registry.hpp): its kind, given by the registration, and the values of its
/// number parameters in its descriptor's `parameters` order. What they mean is the method's own
/// business (its descriptor's hooks read them); the library only carries them.
struct RegisteredMethodParams {
  static constexpr int kMaxParameters = 4;
  MethodKind kind{};
  std::array<double, kMaxParameters> values{};
  bool operator==(const RegisteredMethodParams&) const = default;
};

/// One alternative per built-in method, in MethodKind's order (kind_of() is the alternative's
/// index), then one for every registered method.
using MethodParams =
    std::variant<CentralDifferenceParams, BackwardEulerParams, NewmarkParams, HhtParams,
                 GeneralizedAlphaParams, BatheParams, RhoBatheParams, TrBdf2Params, HouboltParams,
                 WilsonThetaParams, NohBatheParams, KimExplicitParams, KrAlphaParams,
                 RegisteredMethodParams>;

MethodKind kind_of(const MethodParams& params);
/// Default parameters of a method.
MethodParams default_params(MethodKind kind);
/// First invalid field ("delta", "beta", "alpha", "rho_inf", …), or nothing.
std::optional<ParameterError> validate(const MethodParams& params);

/// eq. 13
BetaGamma newmark_from_delta(double delta);

/// The one-step implicit family every implicit method here belongs to:
///   u₁ = u₀ + Δt·v₀ + Δt²·(b0·a₀ + b1·a₁)
///   v₁ = v₀ + Δt·(g0·a₀ + g1·a₁)
///   (1−α_m)·M·a₁ + α_m·M·a₀ + (1−α_f)·(C·v₁ + K·u₁) + α_f·(C·v₀ + K·u₀)
///       + G^T·(w·λ₁ + (1−w)·λ₀) = 0
/// Newmark: b0 = ½−β, b1 = β, g0 = 1−γ, g1 = γ, α_m = α_f = 0. Backward Euler: b0 = g0 = 0,
/// b1 = g1 = 1. HHT: Newmark with α_f = −α. Generalized-α: Chung & Hulbert's α_m, α_f, β, γ.
/// w = 1 (endpoint contact) or 1−α_f (weighted).
struct ImplicitCoefficients {
  double b0, b1, g0, g1;
  double alpha_m, alpha_f;
  double contact_weight;
};

/// Whether a method's step is one step of the ImplicitCoefficients family (backward Euler,
/// Newmark, HHT, generalized-α): what the batched kernels and ImplicitIntegrator step alone.
/// Central difference, the composite schemes, Houbolt and Wilson-θ are not.
bool is_single_step_implicit(const MethodParams& params);

/// Coefficients of a single-step implicit method (is_single_step_implicit), from its descriptor
/// (each derived in the method's own core/methods/<method>_method.cpp only); a placeholder for
/// the others, which are not stepped by them.
ImplicitCoefficients implicit_coefficients(const MethodParams& params);

/// The composite schemes' two sub-steps, each a member of the ImplicitCoefficients family
/// stepped by the same integrators (core/methods/bathe_composite.hpp):
/// - `first`: the trapezoidal rule over γ·Δt (step `gamma`·Δt);
/// - `second`: over Δt from the predictors u* = u₀ + Δt·(q0·v₀ + q1·v_γ) + q2·Δt·v*,
///   v* = v₀ + Δt·(q0·a₀ + q1·a_γ): b0 = g0 = 0, b1 = q2², g1 = q2.
struct CompositeCoefficients {
  double gamma;       ///< sub-step ratio γ
  double q0, q1, q2;  ///< the second sub-step's weights
  ImplicitCoefficients first, second;
};

/// Coefficients of a composite method (Bathe, ρ∞-Bathe, TR-BDF2), from its descriptor; Bathe's
/// for a method that is none.
CompositeCoefficients composite_coefficients(const MethodParams& params);
/// The composite coefficients at high-frequency spectral radius ρ∞ and sub-step ratio γ; derived
/// here and only here.
CompositeCoefficients composite_step_coefficients(double rho_inf, double gamma);

/// Whether a method is stepped as a composite scheme (core/methods/bathe_composite.hpp).
bool is_composite(const MethodParams& params);

/// Houbolt's steps, each a member of the ImplicitCoefficients family stepped from predictors
/// u*, v* written into the state (b0 = g0 = α_m = α_f = 0, so u₁ = u* + b1·Δt²·a₁,
/// v₁ = v* + g1·Δt·a₁; core/methods/houbolt.hpp forms u* and v*):
/// - `steady`: b1 = ½, g1 = 11/12, Houbolt's formulas solved for u_{n+1} and v_{n+1};
/// - `first`, `second`: the start-up (core/methods/houbolt.hpp): the cubic through u₀, v₀, a₀ and
/// u₁ is
///   the linear-acceleration step (b1 = 1/6, g1 = ½, from u₀, v₀, a₀ with b0 = 1/3, g0 = ½), and
///   the cubic through u₀, v₀, u₁, u₂ gives b1 = 2/5, g1 = 4/5.
struct HouboltCoefficients {
  ImplicitCoefficients first, second, steady;
};
HouboltCoefficients houbolt_coefficients();

/// Wilson-θ's step: θ and the linear-acceleration member of the family (b0 = 1/3, b1 = 1/6,
/// g0 = g1 = ½) taken over θ·Δt (core/methods/wilson_theta.hpp).
struct WilsonThetaCoefficients {
  double theta;
  ImplicitCoefficients extended;
};
WilsonThetaCoefficients wilson_theta_coefficients(const WilsonThetaParams& params);

/// The Noh–Bathe explicit scheme's sub-step ratio and velocity weights (NohBatheParams).
struct NohBatheCoefficients {
  double p;
  double q0, q1, q2;
};
NohBatheCoefficients noh_bathe_coefficients(const NohBatheParams& params);

/// Ω_crit(p) = ω_max·Δt_crit of the Noh–Bathe explicit scheme without damping, p ∈ [½, 1): the
/// largest Ω at which both eigenvalues of its amplification matrix lie in the closed unit disk
/// (Jury's conditions |det| <= 1, |trace| <= 1 + det on the formulas at NohBatheParams):
///   1 − trace + det >= 0 (eigenvalue +1):   Ω² <= 4/((1 − p)(3p − 1));
///   det >= −1:                              Ω⁴ <= 8/((1 − p)²(2p − 1));
///   1 + trace + det >= 0 (eigenvalue −1):   with c = (1 − p)(4p² − 3p + 1), only when c < ¼
///                                           (p > ¾): Ω² <= 8/(1 + √(1 − 4c)).
/// The smallest bound holds: 4 at p = ½ (two central-difference half steps), 3.7450 at p = 0.54,
/// 2√3 = 3.4641 at p = ⅔ (the least on [½, ¾]), 3.5777 at p = ¾; just above ¾ the eigenvalue −1
/// condition starts to bind and Ω_crit drops to 2√2 = 2.83, then falls towards 2 as p → 1 (no
/// better than central difference's per step, at twice its cost). NaN outside [½, 1).
double noh_bathe_critical_omega(double p);

/// The weights of Kim's two-stage explicit scheme (KimExplicitParams), in units of Δt and Δt²:
///   ũ₁ = u₀ + Δt·v₀ + Δt²·(u0·a₀ + up·a_p),   ṽ₁ = v₀ + Δt·(v0·a₀ + vp·a_p),
///   D = d0·a₀ + dp·a_p + d1·a₁,   u₁ = ũ₁ + cu·Δt²·D,   v₁ = ṽ₁ + cv·Δt·D.
struct KimExplicitCoefficients {
  double p;
  double u0, up;      ///< (1 − 1/(3p))/2, 1/(6p)
  double v0, vp;      ///< 1 − 1/(2p), 1/(2p)
  double d0, dp, d1;  ///< 1/p, −1/(p(1 − p)), 1/(1 − p)
  double cu, cv;      ///< (1 − 2p)/12 (exactly 0 at p = ½: u₁ = ũ₁), (2 − 3p)/6
};
KimExplicitCoefficients kim_explicit_coefficients(const KimExplicitParams& params);

/// Ω_crit(p) = ω_max·Δt_crit of Kim's two-stage explicit scheme without damping, p ∈ [⅓, ½]: the
/// largest Ω at which the three eigenvalues of its amplification matrix lie in the closed unit
/// disk. With X = Ω², its characteristic polynomial P(λ) = λ³ + … (Jury's conditions) gives
///   P(1) = X·(12p − (1 − p)·X)/(12p) >= 0 (eigenvalue +1):   X <= 12p/(1 − p);
///   −P(−1) >= 0 (eigenvalue −1):  X below the least positive root of
///       (12p³ − 6p² − 3p + 1)·X² − 12(5p − 1)(p − 1)·X + 144p(p − 1) = 0, real from p ≈ 0.4418;
/// the complex-pair condition does not bind on [⅓, ½]. √6 = 2.4495 at p = ⅓ and at p = ½,
/// 2√2 at p = 0.4, the largest 3.0815 at p = 0.4418 where the two bounds meet. NaN outside
/// [⅓, ½]. (Computed from the matrix of core/spectral/amplification.cpp;
/// tests/kim_explicit_test.cpp checks it against the spectral radius.)
double kim_explicit_critical_omega(double p);

/// KR-α's scalar parameters from ρ∞ (KrAlphaParams; Chung & Hulbert's, as generalized-α's):
/// the matrices α1, α2, α3 are built from them and the system's M, C, K
/// (core/methods/kr_alpha.hpp).
struct KrAlphaCoefficients {
  double alpha_m, alpha_f;
  double beta, gamma;
};
KrAlphaCoefficients kr_alpha_coefficients(const KrAlphaParams& params);

/// γ₀(ρ∞) = (2 − √(2 + 2ρ∞))/(1 − ρ∞), ½ at ρ∞ = 1: ρ∞-Bathe's default sub-step ratio.
double rho_bathe_default_gamma(double rho_inf);

/// β and γ a method of the Newmark family uses, for reports; nothing for the others (central
/// difference, backward Euler, the composite schemes, Houbolt, Wilson-θ).
std::optional<BetaGamma> reported_beta_gamma(const MethodParams& params);

}  // namespace impactid
