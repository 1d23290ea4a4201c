#include "core/model/sparse_system.hpp"

namespace impactid {

double SparseSystem::energy(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
  return 0.5 * quadratic_form(mass, v) + 0.5 * quadratic_form(stiffness, u);
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
