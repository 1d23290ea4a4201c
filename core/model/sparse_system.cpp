#include "core/model/sparse_system.hpp"

#include <cstring>

namespace impactid {

double SparseSystem::energy(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
  const double e = 0.5 * quadratic_form(mass, v) + 0.5 * quadratic_form(stiffness, u);
  return load.active() ? e + load.potential(u) : e;
}

void multiply(const SparseMatrix& a, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.setZero();
  multiply_add(a, 1.0, x, y);
}

void multiply_add(const SparseMatrix& a, double s, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    const double sx = s * x[j];
    if (sx == 0.0) continue;
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) y[it.row()] += it.value() * sx;
  }
}

double quadratic_form(const SparseMatrix& a, const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    double column = 0.0;
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) column += it.value() * x[it.row()];
    sum += x[j] * column;
  }
  return sum;
}

bool stores_diagonal_only(const SparseMatrix& a) {
  if (!a.isCompressed() || a.rows() != a.cols() || a.nonZeros() != a.rows()) return false;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    if (a.outerIndexPtr()[j] != j || a.innerIndexPtr()[j] != j) return false;
  }
  return true;
}

bool is_exactly_symmetric(const SparseMatrix& a) {
  if (!a.isCompressed() || a.rows() != a.cols()) return false;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (int e = a.outerIndexPtr()[j] + 1; e < a.outerIndexPtr()[j + 1]; ++e) {
      if (a.innerIndexPtr()[e - 1] >= a.innerIndexPtr()[e]) return false;
    }
  }
  const SparseMatrix transpose = a.transpose();  // compressed, rows sorted
  if (transpose.nonZeros() != a.nonZeros()) return false;
  const auto same = [](const auto* x, const auto* y, Eigen::Index count) {
    return count == 0 || std::memcmp(x, y, sizeof(*x) * static_cast<std::size_t>(count)) == 0;
  };
  return same(a.outerIndexPtr(), transpose.outerIndexPtr(), a.outerSize() + 1) &&
         same(a.innerIndexPtr(), transpose.innerIndexPtr(), a.nonZeros()) &&
         same(a.valuePtr(), transpose.valuePtr(), a.nonZeros());
}

bool is_diagonal(const SparseMatrix& a) {
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
      if (it.row() != j && it.value() != 0.0) return false;
    }
  }
  return true;
}

std::optional<Tridiagonal> as_tridiagonal(const SparseMatrix& a) {
  const Eigen::Index n = a.rows();
  if (a.cols() != n) return std::nullopt;
  Tridiagonal t = Tridiagonal::zero(n);
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
      const Eigen::Index i = it.row();
      if (it.value() == 0.0) continue;
      if (i == j) {
        t.diag[i] = it.value();
      } else if (i == j + 1) {
        t.lower[i] = it.value();
      } else if (j == i + 1) {
        t.upper[i] = it.value();
      } else {
        return std::nullopt;
      }
    }
  }
  return t;
}

SparseMatrix to_sparse(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(3 * n));
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i > 0 && a.lower[i] != 0.0) entries.emplace_back(i, i - 1, a.lower[i]);
    if (a.diag[i] != 0.0) entries.emplace_back(i, i, a.diag[i]);
    if (i + 1 < n && a.upper[i] != 0.0) entries.emplace_back(i, i + 1, a.upper[i]);
  }
  SparseMatrix out(n, n);
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

}  // namespace impactid
