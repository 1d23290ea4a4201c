#include "core/algebra/contact_lcp.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace impactid {

namespace {

// Storage of one solve: the Cholesky factor of D_SS (row stride ld), its right-hand side, the
// active set and membership. Fixed arrays for the scenes of bodies, ContactLcpWorkspace for models.
struct LcpStorage {
  double* l;
  int ld;
  double* y;
  int* active;
  int* in;  // 1: in the active set
};

// Solves D_SS·x = p_S by Cholesky (D_SS is positive definite) for the indices of `active`
// (count of them), writing x into mu at those indices. Returns false on a non-positive pivot.
bool solve_active(const double* d, const double* p, int m, const int* active, int count, double* mu,
                  const LcpStorage& s) {
  if (count == 1) {  // one active constraint: p/d, as the single-wall solvers compute it
    const int k = active[0];
    if (!(d[k + m * k] > 0.0)) return false;
    mu[k] = p[k] / d[k + m * k];
    return true;
  }
  double* l = s.l;
  double* y = s.y;
  const int ld = s.ld;
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j <= i; ++j) {
      double sum = d[active[i] + m * active[j]];
      for (int k = 0; k < j; ++k) sum -= l[i * ld + k] * l[j * ld + k];
      if (i == j) {
        if (!(sum > 0.0)) return false;
        l[i * ld + i] = std::sqrt(sum);
      } else {
        l[i * ld + j] = sum / l[j * ld + j];
      }
    }
  }
  for (int i = 0; i < count; ++i) {
    double sum = p[active[i]];
    for (int k = 0; k < i; ++k) sum -= l[i * ld + k] * y[k];
    y[i] = sum / l[i * ld + i];
  }
  for (int i = count - 1; i >= 0; --i) {
    double sum = y[i];
    for (int k = i + 1; k < count; ++k) sum -= l[k * ld + i] * y[k];
    y[i] = sum / l[i * ld + i];
  }
  for (int i = 0; i < count; ++i) mu[active[i]] = y[i];
  return true;
}

int solve(const double* d, const double* p, int m, double* mu, const LcpStorage& s, int cap) {
  int* in = s.in;
  int* active = s.active;
  double scale = 0.0;
  for (int k = 0; k < m; ++k) {
    in[k] = p[k] > 0.0 ? 1 : 0;
    scale = std::max(scale, std::abs(p[k]));
  }
  const double tolerance = kContactLcpTolerance * scale;
  int flips = 0;
  for (;;) {
    int count = 0;
    for (int k = 0; k < m; ++k) {
      mu[k] = 0.0;
      if (in[k]) active[count++] = k;
    }
    if (count > 0 && !solve_active(d, p, m, active, count, mu, s)) break;
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
    in[violated] = in[violated] ? 0 : 1;
    ++flips;
  }
  for (int k = 0; k < m; ++k) mu[k] = mu[k] > 0.0 ? mu[k] : 0.0;
  return flips;
}

}  // namespace

int solve_contact_lcp(const double* d, const double* p, int m, double* mu) {
  std::array<double, kMaxConstraints * kMaxConstraints> l{};
  std::array<double, kMaxConstraints> y{};
  std::array<int, kMaxConstraints> active{};
  std::array<int, kMaxConstraints> in{};
  const int cap = (m < 20 ? (1 << m) : (1 << 20)) + 16;
  return solve(d, p, m, mu, {l.data(), kMaxConstraints, y.data(), active.data(), in.data()}, cap);
}

void ContactLcpWorkspace::resize(int m) {
  const auto size = static_cast<std::size_t>(m);
  factor.assign(size * size, 0.0);
  rhs.assign(size, 0.0);
  active.assign(size, 0);
  in.assign(size, 0);
  capacity = m;
}

int solve_contact_lcp(const double* d, const double* p, int m, double* mu, ContactLcpWorkspace& w) {
  assert(m <= w.capacity);
  const int cap = 64 * m + 1024;
  return solve(d, p, m, mu, {w.factor.data(), m, w.rhs.data(), w.active.data(), w.in.data()}, cap);
}

bool is_positive_diagonal(const double* d, int m) {
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      if (i == j ? !(d[i + m * j] > 0.0) : d[i + m * j] != 0.0) return false;
    }
  }
  return true;
}

int solve_diagonal_contact_lcp(const double* d, const double* p, int m, double* mu) {
  int count = 0;
  for (int k = 0; k < m; ++k) count += p[k] > 0.0 ? 1 : 0;
  for (int k = 0; k < m; ++k) {
    const double dk = d[k + m * k];
    if (!(p[k] > 0.0)) {
      mu[k] = 0.0;
    } else if (count == 1) {
      mu[k] = p[k] / dk;  // solve_active's one-constraint answer
    } else {
      const double l = std::sqrt(dk);  // the Cholesky factor's diagonal; its other entries are 0
      mu[k] = (p[k] / l) / l;
    }
  }
  return 0;
}

}  // namespace impactid
