// What the spectral analysis (core/spectral/amplification.hpp) needs of one method, carried by its
// descriptor (core/methods/method_registry.hpp): its amplification matrix on the undamped
// oscillator ü + ω²·u = 0, the eigenvalues of that matrix from a well-conditioned similar one,
// its high-frequency limit and its stability limit. The analysis loops over none of the methods:
// it validates, then calls these. Also the small eigenvalue tools the methods' hooks share.
//
// Every hook assumes valid params (validate() passed) and Ω = ω·Δt finite and >= 0; the
// analysis checks both first. Pure functions, thread-safe.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "core/methods/method.hpp"

namespace impactid {

/// The eigenvalues are computed in long double (core/spectral/amplification.cpp says why).
using SpectralScalar = long double;
using SpectralEigenvalue = std::complex<SpectralScalar>;
using SpectralMatrix = Eigen::Matrix<SpectralScalar, Eigen::Dynamic, Eigen::Dynamic>;

struct MethodSpectrum {
  /// Rows (and columns) of the amplification matrix: 2 for a two-step recurrence on
  /// (u_n, u_{n−1}), 3 otherwise; a NaN matrix of this size stands for invalid input.
  int size;
  /// A(Ω) in double, as amplification_matrix() documents it for this method.
  Eigen::MatrixXd (*amplification)(const MethodParams& params, double omega_dt);
  /// The eigenvalues of A(Ω), from a similar matrix that stays well conditioned as Ω → 0 and
  /// Ω → ∞; empty when A(Ω) is not finite.
  std::vector<SpectralEigenvalue> (*eigenvalues)(const MethodParams& params, double omega_dt);
  /// ρ∞ = lim_{Ω→∞} ρ(Ω) (high_frequency_spectral_radius documents each method's).
  double (*high_frequency_radius)(const MethodParams& params);
  /// The largest stable Ω without damping: +inf for the implicit methods.
  double (*stability_limit)(const MethodParams& params);
};

inline constexpr double kSpectralNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kSpectralInf = std::numeric_limits<double>::infinity();

/// Appends the eigenvalues of b: isolated diagonal entries first, then Eigen's real Schur solver
/// on the balanced rest.
void append_eigenvalues(SpectralMatrix b, std::vector<SpectralEigenvalue>& out);
/// max |λ|; 0 for none.
SpectralScalar largest_modulus(const std::vector<SpectralEigenvalue>& lambda);
/// The eigenvalues of a one-step matrix b = A(Ω) on (u, Δt·v, Δt²·a): empty if b is not finite;
/// for 0 < Ω < 1 taken on (u, v/ω, a/ω²); past Ω = 1, with `explicit_acceleration` (an
/// explicit method, whose Δt²·a₁ grows like Ω²), on (u, Δt·v, Δt²·a/Ω²).
std::vector<SpectralEigenvalue> one_step_eigenvalues(SpectralMatrix b, double omega_dt,
                                                     bool explicit_acceleration = false);

/// Hooks shared by several methods.
double unbounded_high_frequency_radius(const MethodParams& params);  ///< +inf: explicit
double no_stability_limit(const MethodParams& params);               ///< +inf: implicit

// The 3×3 matrix of the implicit family on x = (u, V, A) = (u, Δt·v, Δt²·a). The equation of
// motion is taken as
//   s·(1−α_f)·u₁ + t·(1−α_m)·A₁ = −s·α_f·u₀ − t·α_m·A₀
// with (s, t) = (Ω², 1), or (1, 1/Ω²) for Ω > 1 so that no entry grows with Ω. With
// u₁ = P + b1·A₁, P = u₀ + V₀ + b0·A₀, and D = t·(1−α_m) + s·(1−α_f)·b1:
//   A₁ = −(s·u₀ + s(1−α_f)·V₀ + (s(1−α_f)·b0 + t·α_m)·A₀)/D,
//   u₁ = (t(1−α_m)·P − b1·(s·α_f·u₀ + t·α_m·A₀))/D,
//   V₁ = V₀ + g0·A₀ + g1·A₁, collected over D.
// Written this way no entry is a difference of nearly equal O(1) terms: u₁ → 0 as Ω → ∞
// (e.g. backward Euler's u₁ = (u₀ + V₀)/(1 + Ω²)) keeps its relative accuracy.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> implicit_amplification(const ImplicitCoefficients& c, double omega_dt) {
  const Scalar omega = omega_dt, omega2 = omega * omega, one = 1;
  const Scalar b0 = c.b0, b1 = c.b1, g0 = c.g0, g1 = c.g1;
  const Scalar mass_m = one - Scalar(c.alpha_m), alpha_m = c.alpha_m;
  const Scalar stiff_f = one - Scalar(c.alpha_f), alpha_f = c.alpha_f;
  const Scalar s = omega_dt > 1.0 ? one : omega2;
  const Scalar t = omega_dt > 1.0 ? one / omega2 : one;
  const Scalar d = t * mass_m + s * stiff_f * b1;
  if (d == Scalar(0) || !std::isfinite(static_cast<double>(d))) {
    return Eigen::Matrix<Scalar, 3, 3>::Constant(Scalar(kSpectralNaN));
  }
  Eigen::Matrix<Scalar, 3, 3> a;
  // clang-format off
  a << t * mass_m - b1 * s * alpha_f,  // u₁
       t * mass_m,
       t * mass_m * b0 - b1 * t * alpha_m,
       -g1 * s,                         // V₁
       t * mass_m + s * stiff_f * (b1 - g1),
       g0 * t * mass_m + s * stiff_f * (g0 * b1 - g1 * b0) - g1 * t * alpha_m,
       -s,                              // A₁
       -s * stiff_f,
       -(s * stiff_f * b0 + t * alpha_m);
  // clang-format on
  return a / d;
}

}  // namespace impactid
