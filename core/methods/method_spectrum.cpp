#include "core/methods/method_spectrum.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <utility>

namespace impactid {
namespace {

using Extended = SpectralScalar;
using ComplexExtended = SpectralEigenvalue;
using MatrixExtended = SpectralMatrix;

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

}  // namespace

// A row or column whose off-diagonal part is zero isolates its diagonal entry as an eigenvalue
// and is removed first (backward Euler's matrix ignores a₀: its third column is zero), then the
// rest is balanced and handed to Eigen's real Schur solver.
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

SpectralScalar largest_modulus(const std::vector<SpectralEigenvalue>& lambda) {
  Extended rho = 0;
  for (const ComplexExtended& l : lambda) rho = std::max(rho, std::abs(l));
  return rho;
}

std::vector<SpectralEigenvalue> one_step_eigenvalues(SpectralMatrix b, double omega_dt,
                                                     bool explicit_acceleration) {
  std::vector<ComplexExtended> lambda;
  const Extended omega = omega_dt;
  if (!b.allFinite()) return {};
  if (omega > 0 && omega < 1) {
    const Eigen::Matrix<Extended, 3, 1> d(1, omega, omega * omega);
    b = d.cwiseInverse().asDiagonal() * b * d.asDiagonal();
  }
  if (omega > 1 && explicit_acceleration) {
    // Explicit: u₁ stays O(1) and Δt²·a₁ grows like Ω²; on (u, Δt·v, Δt²·a/Ω²) no entry does.
    const Eigen::Matrix<Extended, 3, 1> d(1, 1, omega * omega);
    b = d.cwiseInverse().asDiagonal() * b * d.asDiagonal();
  }
  append_eigenvalues(std::move(b), lambda);
  return lambda;
}

double unbounded_high_frequency_radius(const MethodParams&) {
  return kSpectralInf;
}

double no_stability_limit(const MethodParams&) {
  return kSpectralInf;
}

}  // namespace impactid
