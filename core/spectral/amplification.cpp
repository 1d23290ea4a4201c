#include "core/spectral/amplification.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <utility>
#include <vector>

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool is_central_difference(const MethodParams& params) {
  return kind_of(params) == MethodKind::central_difference;
}

bool valid_omega(double omega_dt) {
  return std::isfinite(omega_dt) && omega_dt >= 0.0;
}

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
    return Eigen::Matrix<Scalar, 3, 3>::Constant(Scalar(kNaN));
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

// A composite scheme's step (core/methods/bathe_composite.hpp) on x = (u, Δt·v, Δt²·a): the
// trapezoidal sub-step over γ·Δt is the family's matrix at γ·Ω on its own scaled state D·x, D =
// diag(1, γ, γ²), so x_γ = D⁻¹·A₁(γΩ)·D·x. The second sub-step, row by row over x:
//   V* = V + q0·A + q1·A_γ,   u* = u + q0·V + q1·V_γ + q2·V*,
//   u₁ = u*/(1 + q2²·Ω²),     A₁ = −Ω²·u₁,   V₁ = V* + q2·A₁,
// with A₁ = −u*/(1/Ω² + q2²) past Ω = 1 so that no entry grows with Ω.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> composite_amplification(const CompositeCoefficients& c,
                                                    double omega_dt) {
  using Matrix = Eigen::Matrix<Scalar, 3, 3>;
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar gamma = c.gamma, q0 = c.q0, q1 = c.q1, q2 = c.q2, omega = omega_dt;
  const Eigen::Matrix<Scalar, 3, 1> d(1, gamma, gamma * gamma);
  const Matrix first = d.cwiseInverse().asDiagonal() *
                       implicit_amplification<Scalar>(c.first, c.gamma * omega_dt) * d.asDiagonal();
  if (!first.allFinite()) return Matrix::Constant(Scalar(kNaN));
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row v_star = e_v + q0 * e_a + q1 * first.row(2);
  const Row u_star = e_u + q0 * e_v + q1 * first.row(1) + q2 * v_star;
  const Row u1 = u_star / (1 + q2 * q2 * omega * omega);
  const Row a1 =
      omega_dt > 1.0 ? Row(-u_star / (1 / (omega * omega) + q2 * q2)) : Row(-omega * omega * u1);
  Matrix a;
  a.row(0) = u1;
  a.row(1) = v_star + q2 * a1;
  a.row(2) = a1;
  return a;
}

// Wilson-θ's step (core/methods/wilson_theta.hpp) on x = (u, Δt·v, Δt²·a): equilibrium at t + θΔt,
//   A_θ = −s·(u + θ·V + θ²/3·A)/(t + s·θ²/6)   ((s, t) as in implicit_amplification),
// then A₁ = (1 − 1/θ)·A + A_θ/θ, V₁ = V + (A + A₁)/2, u₁ = u + V + (2A + A₁)/6.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> wilson_theta_amplification(double theta_value, double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar theta = theta_value, omega = omega_dt, one = 1;
  const Scalar s = omega_dt > 1.0 ? one : omega * omega;
  const Scalar t = omega_dt > 1.0 ? one / (omega * omega) : one;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row a_theta = Row(1, theta, theta * theta / 3) * (-s / (t + s * theta * theta / 6));
  const Row a1 = (one - one / theta) * e_a + a_theta / theta;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = e_u + e_v + e_a / 3 + a1 / 6;
  a.row(1) = e_v + e_a / 2 + a1 / 2;
  a.row(2) = a1;
  return a;
}

// Houbolt's recurrence (2 + Ω²)·u_{n+1} = 5u_n − 4u_{n−1} + u_{n−2} (core/methods/houbolt.hpp
// without damping and contact) as the companion matrix on y_n = (u_n, u_{n−1}, u_{n−2}).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> houbolt_companion(double omega_dt) {
  const Scalar omega = omega_dt, d = 2 + omega * omega;
  Eigen::Matrix<Scalar, 3, 3> a;
  // clang-format off
  a << 5 / d, -4 / d, 1 / d,
       1,     0,      0,
       0,     1,      0;
  // clang-format on
  return a;
}

// The Noh–Bathe explicit step (core/methods/noh_bathe.hpp without damping and contact) on
// x = (u, Δt·v, Δt²·a), composed from its two sub-steps row by row:
//   u_p = u + p·V + p²/2·A,                 A_p = −Ω²·u_p,   V_p = V + p/2·(A + A_p),
//   u₁ = u_p + (1−p)·V_p + (1−p)²/2·A_p,    A₁ = −Ω²·u₁,
//   V₁ = V_p + (1−p)·(q0·A + (½ + q1)·A_p + q2·A₁).
// Entries grow like Ω⁴, harmless within the explicit limit (Ω_crit <= 4).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> noh_bathe_amplification(const NohBatheCoefficients& c,
                                                    double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar p = c.p, r = 1 - p, q0 = c.q0, q1 = c.q1, q2 = c.q2, omega = omega_dt;
  const Scalar w2 = omega * omega, half = Scalar(1) / 2;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row u_p = e_u + p * e_v + (p * p / 2) * e_a;
  const Row a_p = -w2 * u_p;
  const Row v_p = e_v + (p / 2) * (e_a + a_p);
  const Row u1 = u_p + r * v_p + (r * r / 2) * a_p;
  const Row a1 = -w2 * u1;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u1;
  a.row(1) = v_p + r * (q0 * e_a + (half + q1) * a_p + q2 * a1);
  a.row(2) = a1;
  return a;
}

// Kim's two-stage explicit step (core/methods/kim_explicit.hpp without damping and contact) on
// x = (u, Δt·v, Δt²·a), composed from its stages row by row:
//   u_p = u + p·V + p²/2·A,                  A_p = −Ω²·u_p,
//   ũ₁ = u + V + u0·A + up·A_p,   Ṽ₁ = V + v0·A + vp·A_p,   A₁ = −Ω²·ũ₁,
//   D = d0·A + dp·A_p + d1·A₁,    u₁ = ũ₁ + cu·D,   V₁ = Ṽ₁ + cv·D.
// Entries grow like Ω⁴, harmless within the explicit limit (Ω_crit <= 3.09).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> kim_explicit_amplification(const KimExplicitCoefficients& c,
                                                       double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar p = c.p, omega = omega_dt;
  const Scalar w2 = omega * omega;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row u_p = e_u + p * e_v + (p * p / 2) * e_a;
  const Row a_p = -w2 * u_p;
  const Row u_predicted = e_u + e_v + Scalar(c.u0) * e_a + Scalar(c.up) * a_p;
  const Row v_predicted = e_v + Scalar(c.v0) * e_a + Scalar(c.vp) * a_p;
  const Row a1 = -w2 * u_predicted;
  const Row d = Scalar(c.d0) * e_a + Scalar(c.dp) * a_p + Scalar(c.d1) * a1;
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u_predicted + Scalar(c.cu) * d;
  a.row(1) = v_predicted + Scalar(c.cv) * d;
  a.row(2) = a1;
  return a;
}

// The KR-α explicit step (core/methods/kr_alpha.hpp without damping and contact) on the reported
// state x = (u, Δt·v, Δt²·a): with D = 1 + βΩ², α1 = 1/D, N = α_m + α_f·βΩ², E = D − N (D·α3 = N,
// D·(1 − α3) = E) and the method's own velocity V̂ = V − γ·α1·A,
//   u₁ = u + V̂ + (½ + γ)·α1·A,   V̂₁ = V̂ + α1·A,
//   A₁ = −(N·A + D·Ω²·((1−α_f)·u₁ + α_f·u))/E   (from (1 − α3)·A₁ + α3·A + Ω²·u_{1−α_f} = 0),
//   V₁ = V̂₁ + γ·α1·A₁:
// similar to the matrix on (u, V̂, A), so the same eigenvalues.
// Explicit, so A₁ grows like Ω²: eigenvalues() rescales it (the third component by Ω²) past Ω = 1.
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> kr_alpha_amplification(const KrAlphaCoefficients& c, double omega_dt) {
  using Row = Eigen::Matrix<Scalar, 1, 3>;
  const Scalar omega = omega_dt, w2 = omega * omega, one = 1;
  const Scalar beta = c.beta, alpha_m = c.alpha_m, alpha_f = c.alpha_f;
  const Scalar d = one + beta * w2, n = alpha_m + alpha_f * beta * w2;
  const Scalar e = (one - alpha_m) + (one - alpha_f) * beta * w2;
  const Scalar alpha1 = one / d, half = one / 2, gamma = c.gamma;
  const Row e_u(1, 0, 0), e_v(0, 1, 0), e_a(0, 0, 1);
  const Row v_hat = e_v - (gamma * alpha1) * e_a;
  const Row u1 = e_u + v_hat + ((half + gamma) * alpha1) * e_a;
  const Row a1 = -((n / e) * e_a + (d * w2 / e) * ((one - alpha_f) * u1 + alpha_f * e_u));
  Eigen::Matrix<Scalar, 3, 3> a;
  a.row(0) = u1;
  a.row(1) = v_hat + alpha1 * e_a + (gamma * alpha1) * a1;
  a.row(2) = a1;
  return a;
}

// The one-step matrix of any method but central difference and Houbolt, on (u, Δt·v, Δt²·a).
template <class Scalar>
Eigen::Matrix<Scalar, 3, 3> step_amplification(const MethodParams& params, double omega_dt) {
  if (const auto* noh_bathe = std::get_if<NohBatheParams>(&params)) {
    return noh_bathe_amplification<Scalar>(noh_bathe_coefficients(*noh_bathe), omega_dt);
  }
  if (const auto* kim = std::get_if<KimExplicitParams>(&params)) {
    return kim_explicit_amplification<Scalar>(kim_explicit_coefficients(*kim), omega_dt);
  }
  if (const auto* kr_alpha = std::get_if<KrAlphaParams>(&params)) {
    return kr_alpha_amplification<Scalar>(kr_alpha_coefficients(*kr_alpha), omega_dt);
  }
  if (is_composite(params)) {
    return composite_amplification<Scalar>(composite_coefficients(params), omega_dt);
  }
  if (const auto* wilson = std::get_if<WilsonThetaParams>(&params)) {
    return wilson_theta_amplification<Scalar>(wilson->theta, omega_dt);
  }
  return implicit_amplification<Scalar>(implicit_coefficients(params), omega_dt);
}

Eigen::Matrix2d central_difference_amplification(double omega_dt) {
  Eigen::Matrix2d a;
  a << 2.0 - omega_dt * omega_dt, -1.0, 1.0, 0.0;
  return a;
}

using Extended = long double;
using ComplexExtended = std::complex<Extended>;
using MatrixExtended = Eigen::Matrix<Extended, Eigen::Dynamic, Eigen::Dynamic>;

// Diagonal similarity D⁻¹·B·D with powers of 2 (exact) that equalises the off-diagonal row and
// column norms (Parlett & Reinsch 1969, as LAPACK's xGEBAL without permutations).
void balance(MatrixExtended& b) {
  const Eigen::Index n = b.rows();
  for (int sweep = 0, changed = 1; changed && sweep < 64; ++sweep) {
    changed = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      Extended column = 0, row = 0;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (j == i) continue;
        column += std::abs(b(j, i));
        row += std::abs(b(i, j));
      }
      if (column == 0 || row == 0) continue;
      const Extended before = column + row;
      Extended f = 1;
      while (column < row / 2) column *= 2, row /= 2, f *= 2;
      while (column >= row * 2) column /= 2, row *= 2, f /= 2;
      if (column + row < Extended(0.95) * before) {
        b.col(i) *= f;
        b.row(i) /= f;
        changed = 1;
      }
    }
  }
}

// Eigenvalues of b. A row or column whose off-diagonal part is zero isolates its diagonal entry
// as an eigenvalue and is removed first (backward Euler's matrix ignores a₀: its third column
// is zero), then the rest is balanced and handed to Eigen's real Schur solver.
void append_eigenvalues(MatrixExtended b, std::vector<ComplexExtended>& out) {
  const Eigen::Index n = b.rows();
  for (Eigen::Index i = 0; i < n && n > 1; ++i) {
    bool isolated_column = true, isolated_row = true;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (j == i) continue;
      isolated_column = isolated_column && b(j, i) == 0;
      isolated_row = isolated_row && b(i, j) == 0;
    }
    if (!isolated_column && !isolated_row) continue;
    out.emplace_back(b(i, i), 0);
    MatrixExtended rest(n - 1, n - 1);
    for (Eigen::Index r = 0, rr = 0; r < n; ++r) {
      if (r == i) continue;
      for (Eigen::Index c = 0, cc = 0; c < n; ++c) {
        if (c != i) rest(rr, cc++) = b(r, c);
      }
      ++rr;
    }
    append_eigenvalues(std::move(rest), out);
    return;
  }
  balance(b);
  const auto lambda = Eigen::EigenSolver<MatrixExtended>(b, false).eigenvalues();
  out.insert(out.end(), lambda.begin(), lambda.end());
}

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
  std::vector<ComplexExtended> lambda;
  const Extended omega = omega_dt;
  if (is_central_difference(params)) {
    const Extended sigma = std::min<Extended>(omega, 1);
    if (sigma == 0) return {1, 1};
    MatrixExtended b(2, 2);
    b << 1 - omega * omega, sigma, -omega * omega / sigma, 1;
    append_eigenvalues(std::move(b), lambda);
    return lambda;
  }
  if (kind_of(params) == MethodKind::houbolt) {
    const Extended sigma = std::min<Extended>(omega, 1), w2 = omega * omega, d = 2 + w2;
    if (sigma == 0) return {1, 1, 0.5L};
    MatrixExtended b(3, 3);
    // clang-format off
    b << 2,              2 * sigma,   sigma * sigma,
         -w2 / sigma,    2,           sigma,
         -w2 / (sigma * sigma), -w2 / sigma, 1;
    // clang-format on
    b /= d;
    append_eigenvalues(std::move(b), lambda);
    return lambda;
  }
  MatrixExtended b = step_amplification<Extended>(params, omega_dt);
  if (!b.allFinite()) return {};
  if (omega > 0 && omega < 1) {
    const Eigen::Matrix<Extended, 3, 1> d(1, omega, omega * omega);
    b = d.cwiseInverse().asDiagonal() * b * d.asDiagonal();
  }
  if (omega > 1 && kind_of(params) == MethodKind::kr_alpha) {
    // Explicit: u₁ stays O(1) and Δt²·a₁ grows like Ω²; on (u, Δt·v, Δt²·a/Ω²) no entry does.
    const Eigen::Matrix<Extended, 3, 1> d(1, 1, omega * omega);
    b = d.cwiseInverse().asDiagonal() * b * d.asDiagonal();
  }
  append_eigenvalues(std::move(b), lambda);
  return lambda;
}

SpectralProperties invalid_properties() {
  return {kNaN, kNaN, kNaN, false};
}

Extended largest_modulus(const std::vector<ComplexExtended>& lambda) {
  Extended rho = 0;
  for (const ComplexExtended& l : lambda) rho = std::max(rho, std::abs(l));
  return rho;
}

double spectral_radius(const MethodParams& params, double omega_dt) {
  const std::vector<ComplexExtended> lambda = eigenvalues(params, omega_dt);
  return lambda.empty() ? kNaN : static_cast<double>(largest_modulus(lambda));
}

// Largest modulus of a root of a·λ² + b·λ + c (a > 0). A complex pair has modulus √(c/a)
// exactly (product of the roots), so only the real case uses the discriminant.
double quadratic_root_modulus(double a, double b, double c) {
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant <= 0.0) return std::sqrt(std::abs(c / a));
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  return std::max(std::abs(q / a), q == 0.0 ? 0.0 : std::abs(c / q));
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
  const bool cdm = is_central_difference(params);
  if (validate(params) || !valid_omega(omega_dt)) {
    return Eigen::MatrixXd::Constant(cdm ? 2 : 3, cdm ? 2 : 3, kNaN);
  }
  if (cdm) return central_difference_amplification(omega_dt);
  if (kind_of(params) == MethodKind::houbolt) return houbolt_companion<double>(omega_dt);
  return step_amplification<double>(params, omega_dt);
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
  // Explicit: unstable past Ω_crit, ρ grows like Ω² (central difference) or Ω⁴ (Noh–Bathe,
  // Kim).
  if (is_central_difference(params) || kind_of(params) == MethodKind::noh_bathe ||
      kind_of(params) == MethodKind::kim_explicit) {
    return kInf;
  }
  // Houbolt: past Ω = 1 the backward-difference form of eigenvalues() tends to the strictly lower
  // triangular [[0, 0, 0], [−1, 0, 0], [−1, −1, 0]], nilpotent: ρ∞ = 0 exactly (ρ falls like
  // Ω^(−2/3): (2 + Ω²)·λ³ ≈ 1).
  if (kind_of(params) == MethodKind::houbolt) return 0.0;
  if (const auto* kr_alpha = std::get_if<KrAlphaParams>(&params)) {
    // The limit of kr_alpha_amplification as Ω → ∞ on (u, Δt·v, Δt²·a/Ω²), in closed form
    // (α1·Ω² → 1/β, D/E → 1/(1−α_f), N/E → α_f/(1−α_f) = ρ∞). At ρ∞ = 0 its eigenvalues are a
    // triple root 0, accurate only to about ε^(1/3) ≈ 5e-7 in long double.
    const KrAlphaCoefficients c = kr_alpha_coefficients(*kr_alpha);
    const Extended q = Extended(0.5) + c.gamma, beta = c.beta, r = kr_alpha->rho_inf;
    MatrixExtended b(3, 3);
    // clang-format off
    b << 1,      1,  q / beta,
         0,      1,  1 / beta,
         -1 - r, -1, -q / beta - r;
    // clang-format on
    std::vector<ComplexExtended> lambda;
    append_eigenvalues(std::move(b), lambda);
    return static_cast<double>(largest_modulus(lambda));
  }
  if (const auto* wilson = std::get_if<WilsonThetaParams>(&params)) {
    // The limit of wilson_theta_amplification as Ω → ∞ (s = 1, t = 0), in closed form; its
    // eigenvalues are distinct for θ >= (1 + √3)/2, so accurate to rounding.
    const Extended theta = wilson->theta, t2 = theta * theta, t3 = t2 * theta;
    MatrixExtended b(3, 3);
    // clang-format off
    b << 1 - 1 / t3,  1 - 1 / t2,  (theta - 1) / (2 * theta),
         -3 / t3,     1 - 3 / t2,  (theta - Extended(1.5)) / theta,
         -6 / t3,     -6 / t2,     (theta - 3) / theta;
    // clang-format on
    std::vector<ComplexExtended> lambda;
    append_eigenvalues(std::move(b), lambda);
    return static_cast<double>(largest_modulus(lambda));
  }
  if (is_composite(params)) {
    // A composite scheme: ρ at Ω = 1e8, within about 1e-7 of the limit (the original Bathe
    // scheme gives 5e-8 for its ρ∞ = 0: its spurious roots fall to 0 like 1/Ω).
    return spectral_properties(params, 1e8).spectral_radius;
  }
  const ImplicitCoefficients c = implicit_coefficients(params);
  // Limit matrix singular: the update does not stay bounded as Ω → ∞.
  if (c.b1 <= 0.0 || c.alpha_f >= 1.0) return kInf;
  const double spurious = std::abs(c.alpha_f / (1.0 - c.alpha_f));
  const double principal = quadratic_root_modulus(c.b1, c.g1 + c.b0 - c.b1, c.g0 - c.b0);
  return std::max(spurious, principal);
}

double period_error_coefficient(const MethodParams& params) {
  // Romberg table on r(Ω) = PE(Ω)/Ω² = c + d·Ω² + e·Ω⁴ + …, halving Ω from 0.16 to 0.01.
  // Smaller Ω add rounding error (Ω̄ carries an absolute error ~ε, so r one of ~ε/Ω³ and more),
  // larger ones truncation error where the series converges slowly (generalized-α with
  // ρ∞ = 0). Measured against the closed forms of the tests: 0.16…0.01 gives <= 4e-12, while
  // going down to 0.005 gives ~1e-11 and 0.32…0.02 up to 2e-9 (ρ∞ = 0).
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
  if (is_central_difference(params)) return 2.0;
  if (const auto* noh_bathe = std::get_if<NohBatheParams>(&params)) {
    return noh_bathe_critical_omega(noh_bathe->p);
  }
  if (const auto* kim = std::get_if<KimExplicitParams>(&params)) {
    return kim_explicit_critical_omega(kim->p);
  }
  return kInf;
}

double rod_max_omega_dt(MassMatrix mass, double courant) {
  if (!(courant > 0.0 && std::isfinite(courant))) return kNaN;
  return (mass == MassMatrix::lumped ? 2.0 : 2.0 * std::sqrt(3.0)) * courant;
}

}  // namespace impactid
