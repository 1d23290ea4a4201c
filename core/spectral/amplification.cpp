#include "core/spectral/amplification.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <utility>
#include <vector>

#include "core/methods/method_registry.hpp"
#include "core/methods/method_spectrum.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool valid_omega(double omega_dt) {
  return std::isfinite(omega_dt) && omega_dt >= 0.0;
}

using Extended = SpectralScalar;
using ComplexExtended = SpectralEigenvalue;

// Eigenvalues of A(Ω), computed in long double from a similar matrix that stays well
// conditioned as Ω → 0 and Ω → ∞. In the states of amplification_matrix the principal pair tends
// to a Jordan block at Ω = 0 (u and Δt·v, or u_n and u_{n−1}, become parallel eigenvectors) and
// the entries differ by orders of magnitude at large Ω; both cost digits in Ω̄.
//   implicit: for Ω < 1 the state (u, v/ω, a/ω²), i.e. D⁻¹·A·D with D = diag(1, Ω, Ω²), in
//     which the exact flow is a rotation; then balancing, which at large Ω finds the analogous
//     scaling (for backward Euler (ω·u, v, …), where the pair is a scaled rotation);
//   central difference: the state (u_n, (u_n − u_{n−1})/σ), σ = min(Ω, 1), in which
//     B = [[1 − Ω², σ], [−Ω²/σ, 1]]  (the leapfrog form), not a diagonal similarity.
// The eigenvalues then carry an absolute error of ~ε·‖B‖, so Ω̄ ~ Ω one of relative size ε/Ω
// and PE(Ω)/Ω², which period_error_coefficient extrapolates, one of ε/Ω³. Hence long double
// (ε ≈ 1e-19 on x86-64; where long double is double, e.g. MSVC or AArch64 macOS, Ω̄ keeps
// fewer digits at small Ω). Empty for invalid params or Ω.
std::vector<ComplexExtended> eigenvalues(const MethodParams& params, double omega_dt) {
  if (validate(params) || !valid_omega(omega_dt)) return {};
  return descriptor(params).spectrum->eigenvalues(params, omega_dt);
}

SpectralProperties invalid_properties() {
  return {kNaN, kNaN, kNaN, false};
}

double spectral_radius(const MethodParams& params, double omega_dt) {
  const std::vector<ComplexExtended> lambda = eigenvalues(params, omega_dt);
  return lambda.empty() ? kNaN : static_cast<double>(largest_modulus(lambda));
}

// Brent's localmin (Brent 1973, "Algorithms for Minimization without Derivatives", ch. 5):
// golden-section search with parabolic interpolation on [lo, hi]; f may return +inf.
template <class F>
double brent_minimize(F&& f, double lo, double hi, double absolute_tolerance) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  const double relative_tolerance = std::sqrt(std::numeric_limits<double>::epsilon());
  double a = lo, b = hi;
  double x = a + golden * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0.0, e = 0.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double middle = 0.5 * (a + b);
    const double tol = relative_tolerance * std::abs(x) + absolute_tolerance;
    const double tol2 = 2.0 * tol;
    if (std::abs(x - middle) <= tol2 - 0.5 * (b - a)) break;
    double p = 0.0, q = 0.0, r = 0.0;
    if (std::abs(e) > tol) {  // trial parabola through x, w, v
      r = (x - w) * (fx - fv);
      q = (x - v) * (fx - fw);
      p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      r = e;
      e = d;
    }
    if (std::abs(p) < std::abs(0.5 * q * r) && p > q * (a - x) && p < q * (b - x)) {
      d = p / q;  // parabolic step
      const double u = x + d;
      if (u - a < tol2 || b - u < tol2) d = x < middle ? tol : -tol;
    } else {
      e = (x < middle ? b : a) - x;  // golden-section step
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol ? d : (d > 0.0 ? tol : -tol));
    const double fu = f(u);
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw;
      w = x, fw = fx;
      x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw;
        w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return x;
}

}  // namespace

Eigen::MatrixXd amplification_matrix(const MethodParams& params, double omega_dt) {
  const MethodSpectrum& spectrum = *descriptor(params).spectrum;
  if (validate(params) || !valid_omega(omega_dt)) {
    return Eigen::MatrixXd::Constant(spectrum.size, spectrum.size, kNaN);
  }
  return spectrum.amplification(params, omega_dt);
}

SpectralProperties spectral_properties(const MethodParams& params, double omega_dt) {
  if (!(omega_dt > 0.0)) return invalid_properties();
  const std::vector<ComplexExtended> lambda = eigenvalues(params, omega_dt);
  if (lambda.empty()) return invalid_properties();

  SpectralProperties p{static_cast<double>(largest_modulus(lambda)), kNaN, kNaN, false};
  // Eigen returns real eigenvalues with an imaginary part of exactly zero (1×1 blocks of the
  // real Schur form), so "complex" needs no tolerance.
  const ComplexExtended* principal = nullptr;
  for (const ComplexExtended& l : lambda) {
    if (l.imag() > 0 && (!principal || std::abs(l) > std::abs(*principal))) principal = &l;
  }
  if (principal) {
    const Extended omega_bar = std::atan2(principal->imag(), principal->real());
    p.damping_ratio = static_cast<double>(-std::log(std::abs(*principal)) / omega_bar);
    p.period_error = static_cast<double>(Extended(omega_dt) / omega_bar - 1);
    p.oscillatory = true;
  }
  return p;
}

double high_frequency_spectral_radius(const MethodParams& params) {
  if (validate(params)) return kNaN;
  return descriptor(params).spectrum->high_frequency_radius(params);
}

double period_error_coefficient(const MethodParams& params) {
  // Romberg table on r(Ω) = PE(Ω)/Ω² = c + d·Ω² + e·Ω⁴ + …, halving Ω from 0.16 to 0.01.
  // Smaller Ω add rounding error (Ω̄ carries an absolute error ~ε, so r one of ~ε/Ω³ and more),
  // larger ones truncation error where the series converges slowly (generalized-α with
  // ρ∞ = 0); 0.16…0.01 came closest to the closed forms of tests/amplification_test.cpp (the
  // figures are in the git log).
  constexpr int kLevels = 5;
  constexpr double kLargestOmega = 0.16;
  std::array<std::array<double, kLevels>, kLevels> table{};
  double omega = kLargestOmega;
  for (int k = 0; k < kLevels; ++k, omega *= 0.5) {
    const SpectralProperties p = spectral_properties(params, omega);
    if (!p.oscillatory) return kNaN;
    table[k][0] = p.period_error / (omega * omega);
    double factor = 1.0;
    for (int j = 1; j <= k; ++j) {
      factor *= 4.0;
      table[k][j] = table[k][j - 1] + (table[k][j - 1] - table[k - 1][j - 1]) / (factor - 1.0);
    }
  }
  return table[kLevels - 1][kLevels - 1];
}

double hht_delta_minimizing_period_error(double alpha, std::optional<double> omega_dt) {
  if (!(alpha >= -0.5 && alpha <= 0.0)) return kNaN;
  if (omega_dt && !(std::isfinite(*omega_dt) && *omega_dt > 0.0)) return kNaN;
  const auto objective = [&](double delta) {
    const HhtParams params{.alpha = alpha, .delta = delta};
    const double error = omega_dt ? spectral_properties(params, *omega_dt).period_error
                                  : period_error_coefficient(params);
    return std::isnan(error) ? kInf : std::abs(error);
  };

  constexpr double kLow = 0.0, kHigh = 2.0;
  constexpr int kIntervals = 200;
  constexpr double kSpacing = (kHigh - kLow) / kIntervals;
  int best = -1;
  double best_value = kInf;
  for (int i = 0; i <= kIntervals; ++i) {
    const double value = objective(kLow + i * kSpacing);
    if (value < best_value) best = i, best_value = value;
  }
  if (best < 0) return kNaN;

  const double lo = kLow + std::max(best - 1, 0) * kSpacing;
  const double hi = kLow + std::min(best + 1, kIntervals) * kSpacing;
  double delta = brent_minimize(objective, lo, hi, 1e-12);
  // Brent never evaluates the ends of its interval. A minimum on the boundary of [0, 2] is
  // reported as that boundary exactly, counting values within kTie (relative) as equal: near a
  // boundary minimum the objective differs by less than its own accuracy (~1e-11 for the Ω → 0
  // coefficient) over a few 1e-6 in δ, and Brent then stops anywhere in that flat stretch.
  constexpr double kTie = 1e-10;
  const auto no_worse = [&](double boundary) {
    return objective(boundary) <= objective(delta) * (1.0 + kTie);
  };
  if (best == 0 && no_worse(kLow)) delta = kLow;
  if (best == kIntervals && no_worse(kHigh)) delta = kHigh;
  return delta;
}

double max_spectral_radius(const MethodParams& params, double omega_min, double omega_max,
                           int samples) {
  if (!(omega_min > 0.0 && std::isfinite(omega_max) && omega_max >= omega_min)) return kNaN;
  if (samples < 1 || (samples == 1 && omega_min != omega_max)) return kNaN;
  if (validate(params)) return kNaN;
  const double log_ratio = samples > 1 ? std::log(omega_max / omega_min) / (samples - 1) : 0.0;
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    // The last sample is omega_max itself, not exp(log(…)) rounded.
    const double omega = i == samples - 1 ? omega_max : omega_min * std::exp(i * log_ratio);
    const double rho = spectral_radius(params, omega);
    if (std::isnan(rho)) return kNaN;
    worst = std::max(worst, rho);
  }
  return worst;
}

namespace {

double stability_scan(const MethodParams& params, double omega_max) {
  if (!(omega_max > 0.0 && std::isfinite(omega_max))) return kNaN;
  const double omega_min = std::min(kStabilityScanMinOmega, omega_max);
  const double decades = std::log10(omega_max / omega_min);
  const int samples =
      std::max(2, static_cast<int>(std::ceil(decades * kStabilityScanSamplesPerDecade)) + 1);
  return omega_min == omega_max ? max_spectral_radius(params, omega_max, omega_max, 1)
                                : max_spectral_radius(params, omega_min, omega_max, samples);
}

}  // namespace

bool is_stable(const MethodParams& params, double omega_max, double tolerance) {
  if (!(tolerance >= 0.0)) return false;
  const double rho = stability_scan(params, omega_max);
  return rho <= 1.0 + tolerance;  // false for NaN
}

std::vector<StabilityMapPoint> hht_stability_map(const std::vector<double>& alphas,
                                                 const std::vector<double>& deltas,
                                                 double omega_max) {
  std::vector<StabilityMapPoint> map;
  map.reserve(alphas.size() * deltas.size());
  for (double alpha : alphas) {
    for (double delta : deltas) {
      const double rho = stability_scan(HhtParams{.alpha = alpha, .delta = delta}, omega_max);
      map.push_back({alpha, delta, rho <= 1.0 + kStabilityTolerance, rho});
    }
  }
  return map;
}

double stability_limit_omega(const MethodParams& params) {
  if (validate(params)) return kNaN;
  return descriptor(params).spectrum->stability_limit(params);
}

double rod_max_omega_dt(MassMatrix mass, double courant) {
  if (!(courant > 0.0 && std::isfinite(courant))) return kNaN;
  // A modified mass is its base's away from the contact element (core/model/rod_scene.hpp), and
  // its massless contact DOF, solved statically, only adds mass (or takes away stiffness) at the
  // neighbour once condensed: the bound is the base's.
  const bool lumped_base = mass == MassMatrix::lumped || mass == MassMatrix::redistributed;
  return (lumped_base ? 2.0 : 2.0 * std::sqrt(3.0)) * courant;
}

}  // namespace impactid
