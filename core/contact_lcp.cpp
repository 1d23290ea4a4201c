#include "core/contact_lcp.hpp"

#include <algorithm>
#include <cmath>

namespace impactid {

namespace {

// Solves D_SS·x = p_S by Cholesky (D_SS is positive definite) for the indices of `active`
// (count of them), writing x into mu at those indices. Returns false on a non-positive pivot.
bool solve_active(const double* d, const double* p, int m, const int* active, int count,
                  double* mu) {
  if (count == 1) {  // one active constraint: p/d, as the single-wall solvers compute it
    const int k = active[0];
    if (!(d[k + m * k] > 0.0)) return false;
    mu[k] = p[k] / d[k + m * k];
    return true;
  }
  std::array<double, kMaxConstraints * kMaxConstraints> l{};
  std::array<double, kMaxConstraints> y{};
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j <= i; ++j) {
      double sum = d[active[i] + m * active[j]];
      for (int k = 0; k < j; ++k) sum -= l[i * kMaxConstraints + k] * l[j * kMaxConstraints + k];
      if (i == j) {
        if (!(sum > 0.0)) return false;
        l[i * kMaxConstraints + i] = std::sqrt(sum);
      } else {
        l[i * kMaxConstraints + j] = sum / l[j * kMaxConstraints + j];
      }
    }
  }
  for (int i = 0; i < count; ++i) {
    double sum = p[active[i]];
    for (int k = 0; k < i; ++k) sum -= l[i * kMaxConstraints + k] * y[k];
    y[i] = sum / l[i * kMaxConstraints + i];
  }
  for (int i = count - 1; i >= 0; --i) {
    double sum = y[i];
    for (int k = i + 1; k < count; ++k) sum -= l[k * kMaxConstraints + i] * y[k];
    y[i] = sum / l[i * kMaxConstraints + i];
  }
  for (int i = 0; i < count; ++i) mu[active[i]] = y[i];
  return true;
}

}  // namespace

int solve_contact_lcp(const double* d, const double* p, int m, double* mu) {
  std::array<bool, kMaxConstraints> in{};
  double scale = 0.0;
  for (int k = 0; k < m; ++k) {
    in[k] = p[k] > 0.0;
    scale = std::max(scale, std::abs(p[k]));
  }
  const double tolerance = 1e-12 * scale;
  const int cap = (m < 20 ? (1 << m) : (1 << 20)) + 16;
  int flips = 0;
  for (;;) {
    std::array<int, kMaxConstraints> active{};
    int count = 0;
    for (int k = 0; k < m; ++k) {
      mu[k] = 0.0;
      if (in[k]) active[count++] = k;
    }
    if (count > 0 && !solve_active(d, p, m, active.data(), count, mu)) break;
    int violated = -1;
    for (int k = 0; k < m && violated < 0; ++k) {
      if (in[k]) {
        if (mu[k] < 0.0 && -mu[k] * d[k + m * k] > tolerance) violated = k;
      } else {
        double g = p[k];
        for (int j = 0; j < count; ++j) g -= d[k + m * active[j]] * mu[active[j]];
        if (g > tolerance) violated = k;
      }
    }
    if (violated < 0 || flips >= cap) break;
    in[violated] = !in[violated];
    ++flips;
  }
  for (int k = 0; k < m; ++k) mu[k] = mu[k] > 0.0 ? mu[k] : 0.0;
  return flips;
}

}  // namespace impactid
