// Spectral analysis of the time integrators on the undamped single-degree-of-freedom oscillator
// ü + ω²·u = 0 without contact, as a function of Ω = ω·Δt: the amplification matrix, its
// spectral radius ρ, the algorithmic damping ratio ξ̄ and the relative period error, their limits
// Ω → ∞ and Ω → 0, stability scans, and the HHT δ that minimises the period error (the paper's
// eq. 19 is checked with it, not assumed; Serfőző & Pere 2022, sec. 4.2,
// doi:10.1556/606.2022.00599).
//
// Definitions (Hilber, Hughes & Taylor 1977, doi:10.1002/eqe.4290050306, sec. 3; Chung &
// Hulbert 1993, doi:10.1115/1.2900803, sec. 3):
//   ρ(Ω)   = max |λ_i| over the eigenvalues of the amplification matrix A(Ω);
//   the principal pair λ = a ± i·b (b > 0) is the complex-conjugate pair of largest modulus;
//   Ω̄      = atan2(b, a)                      (numerical frequency times Δt, in (0, π));
//   ξ̄      = −ln(a² + b²)/(2·Ω̄)               (algorithmic damping ratio);
//   (T̄ − T)/T = Ω/Ω̄ − 1                       (relative period error; > 0: too long a period).
// A mode of frequency ω then evolves as exp(−ξ̄·Ω̄·n)·cos(Ω̄·n + φ) after n steps.
//
// Every function is pure and thread-safe (no state, no globals). None throws: an invalid method
// (validate(params) fails) or an invalid Ω gives NaN results, documented per function. Not meant
// for a hot loop (each call solves a 3×3 eigenproblem and allocates).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"

namespace impactid {

/// The one-step amplification matrix of the method on ü + ω²·u = 0 at Ω = ω·Δt (finite, ≥ 0).
///
/// Composite schemes (Bathe, ρ∞-Bathe): 3×3 on the same state, the trapezoidal sub-step's matrix
/// at γ·Ω composed with the second sub-step's (core/spectral/amplification.cpp).
///
/// Wilson-θ: 3×3 on the same state, the linear-acceleration step over θ·Δt followed by the
/// return to t + Δt (core/methods/wilson_theta.hpp).
///
/// Houbolt: 3×3, the companion matrix of its three-step recurrence
/// (2 + Ω²)·u_{n+1} = 5u_n − 4u_{n−1} + u_{n−2} on y_n = (u_n, u_{n−1}, u_{n−2}), y_{n+1} = A·y_n.
/// Its start-up (core/methods/houbolt.hpp) is not part of it.
///
/// Noh–Bathe explicit: 3×3 on the same state, its two explicit sub-steps composed
/// (core/spectral/amplification.cpp); undamped it has det = 1 − (1−p)²(2p−1)·Ω⁴/4 and
/// trace = 2 − Ω² + p²(1−p)·Ω⁴/2 on (u, Δt·v) (the third eigenvalue is 0: a₀ = −ω²u₀).
///
/// Kim's two-stage explicit scheme: 3×3 on the same state, its two stages and the end correction
/// composed (core/spectral/amplification.cpp); its third eigenvalue is not 0 (a is taken at the
/// predicted ũ₁, not at u₁), 0 only at Ω → 0 and at p = ½.
///
/// Implicit family (everything but central difference): 3×3, x_{n+1} = A·x_n with the scaled
/// state x = (u, Δt·v, Δt²·a), from the ImplicitCoefficients equations of core/methods/method.hpp
/// without damping and contact:
///   u₁ = u₀ + Δt·v₀ + Δt²·(b0·a₀ + b1·a₁),   v₁ = v₀ + Δt·(g0·a₀ + g1·a₁),
///   (1−α_m)·a₁ + α_m·a₀ + ω²·((1−α_f)·u₁ + α_f·u₀) = 0.
/// This is the recurrence ImplicitIntegrator steps, mode by mode.
///
/// Central difference: 2×2, the two-step recurrence u_{n+1} = (2 − Ω²)·u_n − u_{n−1} on
/// y_n = (u_n, u_{n−1}), y_{n+1} = A·y_n (the velocity variant does not matter without damping).
///
/// A NaN matrix (3×3, or 2×2 for central difference) if params are invalid, Ω is negative or
/// not finite, or the effective mass (1−α_m) + Ω²·(1−α_f)·b1 is zero.
Eigen::MatrixXd amplification_matrix(const MethodParams& params, double omega_dt);

/// Spectral properties at one Ω; definitions in the file comment.
struct SpectralProperties {
  double spectral_radius;  ///< ρ = max |λ|, over all eigenvalues (spurious ones included)
  double damping_ratio;    ///< ξ̄ of the principal pair; NaN if !oscillatory
  double period_error;  ///< (T̄ − T)/T = Ω/Ω̄ − 1 of the principal pair; NaN if !oscillatory
  bool oscillatory;     ///< false when no eigenvalue is complex (e.g. past a bifurcation)
};

/// Properties at Ω = omega_dt (finite, > 0); all NaN and oscillatory = false for invalid
/// params or Ω. The eigenvalues are computed in long double from a balanced matrix similar to A
/// (for Ω < 1 first scaled to the state (u, v/ω, a/ω²); for central difference the leapfrog
/// state (u_n, (u_n − u_{n−1})/Ω); for Houbolt the backward differences (u_n, ∇u_n/σ, ∇²u_n/σ²),
/// σ = min(Ω, 1)) that stays well conditioned as Ω → 0 and Ω → ∞ (tests/amplification_test.cpp
/// holds the results to closed forms over a grid of Ω).
SpectralProperties spectral_properties(const MethodParams& params, double omega_dt);

/// ρ∞ = lim_{Ω→∞} ρ(Ω), evaluated analytically: dividing the equation of motion by Ω² and
/// letting Ω → ∞ leaves (1−α_f)·u₁ + α_f·u₀ = 0, and the characteristic polynomial of the limit
/// matrix factors into
///   ((1−α_f)·λ + α_f) · (b1·λ² + (g1 + b0 − b1)·λ + (g0 − b0)),
/// a spurious root −α_f/(1−α_f) and the limit of the principal pair. Where that pair is a
/// double root (Newmark in the δ form, HHT with eq. 15, generalized-α) its modulus is only
/// accurate to about √ε ≈ 1e-8, the sensitivity of a double root to rounded coefficients.
/// +inf for central difference (ρ grows like Ω² past Ω = 2), Noh–Bathe explicit and Kim's
/// two-stage explicit scheme (past Ω_crit(p): stability_limit_omega); NaN for invalid params.
/// The composite schemes (Bathe, ρ∞-Bathe) are evaluated numerically instead, ρ(Ω = 1e8), within
/// about 1e-7 of their limit. Houbolt: 0 exactly (its limit matrix is nilpotent; ρ(Ω) falls only
/// like Ω^(−2/3)). Wilson-θ: the largest eigenvalue modulus of its limit matrix in closed form,
/// e.g. 0.77844 at θ = 1.4 and 1 at θ = (1 + √3)/2.
double high_frequency_spectral_radius(const MethodParams& params);

/// The coefficient c of (T̄ − T)/T = c·Ω² + O(Ω⁴) as Ω → 0 (the period error is even in Ω),
/// by Richardson extrapolation of PE(Ω)/Ω² from Ω = 0.16, 0.08, 0.04, 0.02, 0.01, eliminating
/// the Ω² … Ω⁸ terms of PE(Ω)/Ω². Accurate to about 1e-11 (tests/amplification_test.cpp,
/// PeriodErrorCoefficientsMatchClosedForms). The closed forms the tests check: 1/12 for the
/// trapezoidal rule, −1/24 for central difference, 1/3 for backward Euler,
/// α²/8 + 3αδ/4 − α/4 + δ²/4 + 1/12 for HHT with (α, δ), (11ρ∞² − 14ρ∞ + 11)/(24(1+ρ∞)²) for
/// generalized-α, 11/24 for Houbolt, (6θ² − 6θ + 1)/24 for Wilson-θ, −(3p − 2)²/24 for
/// Noh–Bathe explicit, 0 for Kim's two-stage explicit scheme, whose period error is O(Ω⁴).
/// NaN for invalid params or if the principal pair is not oscillatory at those Ω.
double period_error_coefficient(const MethodParams& params);

/// For HHT with independent α and δ (β, γ from eq. 13): the δ ∈ [0, 2] that minimises the
/// magnitude of the period error, at Ω = *omega_dt (finite, > 0), or of its Ω → 0 coefficient
/// (period_error_coefficient) when omega_dt is nullopt.
///
/// Method: a scan of 201 equally spaced δ over [0, 2], then Brent's bracketing minimiser
/// (golden section with parabolic steps) between the neighbours of the best grid point. δ where
/// the principal pair is not oscillatory count as +inf. If the minimum over [0, 2] lies on its
/// boundary (|PE| monotone towards an end), that end is returned exactly (0.0 or 2.0; values
/// within a relative 1e-10 count as ties): the caller can tell a constrained minimum by
/// comparing with the bounds. NaN if α is outside [−0.5, 0], omega_dt is invalid, or no δ gives
/// an oscillatory principal pair.
///
/// Accuracy: a minimiser cannot resolve δ closer than √(2·noise/f'') — about 4e-6 for the
/// Ω → 0 coefficient (noise ~1e-12, f'' = ½), ~1e-8 at finite Ω (Brent's √ε tolerance).
///
/// The Ω → 0 coefficient is the quadratic α²/8 + 3αδ/4 − α/4 + δ²/4 + 1/12 in δ, positive for
/// every α ∈ [−0.5, 0]; its minimiser is exactly the paper's eq. 19, δ = −1.5·α, which lies on
/// the stable side δ ≥ −α. At finite Ω the minimiser moves: for Ω <= 1 it stays near −1.5·α and
/// on the stable side, and eq. 19's |PE| stays close to the minimal one
/// (tests/amplification_test.cpp, HhtDeltaMinimizingPeriodErrorAtFiniteOmega, holds both); at
/// Ω = 2 it can fall on the unstable side, where the period error has no physical use anyway.
double hht_delta_minimizing_period_error(double alpha, std::optional<double> omega_dt);

/// max ρ(Ω) over `samples` log-spaced Ω from omega_min to omega_max, both included
/// (0 < omega_min <= omega_max finite; samples >= 2, or 1 when omega_min == omega_max).
/// NaN for invalid arguments or params.
double max_spectral_radius(const MethodParams& params, double omega_min, double omega_max,
                           int samples);

/// Lower end of the stability scan of is_stable and hht_stability_map. Below it every consistent
/// method has |ρ − 1| = O(Ω²) < ~1e-8, too small to decide against a tolerance; a method with
/// negative algorithmic damping (HHT with δ < −α) already exceeds 1 + 1e-9 well above it.
inline constexpr double kStabilityScanMinOmega = 1e-4;
/// Samples per decade of the stability scan (ρ(Ω) is smooth on a logarithmic axis).
inline constexpr int kStabilityScanSamplesPerDecade = 100;
/// Default slack on ρ <= 1: rounding leaves ρ = 1 methods (trapezoidal rule) a few ulps off.
inline constexpr double kStabilityTolerance = 1e-9;

/// True if ρ(Ω) <= 1 + tolerance over the scan of Ω ∈ [kStabilityScanMinOmega, omega_max]
/// (omega_max finite and > 0; if it is below kStabilityScanMinOmega only omega_max is checked).
/// The limit Ω → ∞ is not included: check high_frequency_spectral_radius for that. For a
/// time-step restriction pass the largest Ω of the model, e.g. rod_max_omega_dt(). Central
/// difference at exactly Ω = 2 has a double eigenvalue −1 (a Jordan block: linear growth); it
/// is computed as ρ = 1 and counts as stable. False for invalid input.
bool is_stable(const MethodParams& params, double omega_max = 1e4,
               double tolerance = kStabilityTolerance);

struct StabilityMapPoint {
  double alpha;    ///< HHT α
  double delta;    ///< HHT δ (eq. 13)
  bool stable;     ///< is_stable(HhtParams{alpha, delta}, omega_max, kStabilityTolerance)
  double max_rho;  ///< max ρ over the same scan; NaN (and stable = false) for invalid α or δ
};

/// is_stable over the grid alphas × deltas, α-major (all δ of alphas[0] first).
/// Finding (tests/amplification_test.cpp, HhtStableIffDeltaAtLeastMinusAlpha): with eq. 13, HHT is
/// unconditionally stable exactly for δ >= −α on α ∈ [−0.5, 0]; below the line ξ̄ ≈ (α+δ)/2·Ω < 0,
/// so ρ > 1 at every small Ω (no time step helps), though just below it by so little that the
/// default tolerance passes it. At α = −0.5 the spurious root reaches −1 as Ω → ∞ (ρ∞ = 1).
std::vector<StabilityMapPoint> hht_stability_map(const std::vector<double>& alphas,
                                                 const std::vector<double>& deltas,
                                                 double omega_max);

/// The largest Ω = ωΔt at which an explicit method is stable without damping: 2 for central
/// difference, Ω_crit(p) for Noh–Bathe (noh_bathe_critical_omega, core/methods/method.hpp: 3.7450
/// at p = 0.54, where ρ = 1 through the eigenvalue +1), Ω_crit(p) for Kim's two-stage scheme
/// (kim_explicit_critical_omega: √6 at p = ⅓). +inf for the implicit methods here (those
/// unstable for some Ω, HHT with δ < −α, are so at every Ω: is_stable); NaN for invalid params.
double stability_limit_omega(const MethodParams& params);

/// Largest Ω = ω_max·Δt of the free rod of uniform elements at Courant number C = c·Δt/h:
/// 2·C for the lumped mass (ω_max = 2c/h) and 2·√3·C for the consistent mass (ω_max =
/// 2√3·c/h), the zig-zag mode of the free-free chain. Contact and supports only lower it. The
/// modified masses take their base's: redistributed the lumped one's, singular the consistent
/// one's (their massless contact DOF has no frequency: condensed out by its static equation, it
/// leaves its neighbour with more mass per stiffness than the interior). NaN if C is not positive
/// and finite.
double rod_max_omega_dt(MassMatrix mass, double courant);

}  // namespace impactid
