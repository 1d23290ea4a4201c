#include "core/tridiagonal.hpp"

#include <cmath>

namespace impactid {

Tridiagonal Tridiagonal::zero(Eigen::Index n) {
  return {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
}

bool Tridiagonal::is_diagonal() const {
  const Eigen::Index n = size();
  if (n <= 1) return true;
  return lower.tail(n - 1).isZero(0.0) && upper.head(n - 1).isZero(0.0);
}

bool Tridiagonal::is_zero() const { return is_diagonal() && diag.isZero(0.0); }

Tridiagonal Tridiagonal::combined(double a, const Tridiagonal& other, double b) const {
  return {a * lower + b * other.lower, a * diag + b * other.diag, a * upper + b * other.upper};
}

void Tridiagonal::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  // Written out rather than y = 0, y += 1·A·x: the same values without the two no-op flops per
  // row, which the batched kernel (core/batched_simulation.cpp) would have to repeat to stay
  // bit-identical.
  const Eigen::Index n = size();
  if (n == 1) {
    y[0] = diag[0] * x[0];
    return;
  }
  y[0] = diag[0] * x[0] + upper[0] * x[1];
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    y[i] = lower[i] * x[i - 1] + diag[i] * x[i] + upper[i] * x[i + 1];
  }
  y[n - 1] = lower[n - 1] * x[n - 2] + diag[n - 1] * x[n - 1];
}

void Tridiagonal::multiply_add(double s, const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const Eigen::Index n = size();
  if (n == 1) {
    y[0] += s * diag[0] * x[0];
    return;
  }
  y[0] += s * (diag[0] * x[0] + upper[0] * x[1]);
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    y[i] += s * (lower[i] * x[i - 1] + diag[i] * x[i] + upper[i] * x[i + 1]);
  }
  y[n - 1] += s * (lower[n - 1] * x[n - 2] + diag[n - 1] * x[n - 1]);
}

double Tridiagonal::quadratic_form(const Eigen::VectorXd& x) const {
  const Eigen::Index n = size();
  double sum = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    double row = diag[i] * x[i];
    if (i > 0) row += lower[i] * x[i - 1];
    if (i + 1 < n) row += upper[i] * x[i + 1];
    sum += x[i] * row;
  }
  return sum;
}

Eigen::MatrixXd Tridiagonal::dense() const {
  const Eigen::Index n = size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a(i, i) = diag[i];
    if (i > 0) a(i, i - 1) = lower[i];
    if (i + 1 < n) a(i, i + 1) = upper[i];
  }
  return a;
}

bool TridiagonalFactorization::factor(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  lower_ratio_.resize(n);
  upper_ratio_.resize(n);
  upper_ratio2_.resize(n);
  inverse_pivot_.resize(n);
  double previous_ratio = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double pivot = a.diag[i] - (i > 0 ? a.lower[i] * previous_ratio : 0.0);
    if (pivot == 0.0 || !std::isfinite(pivot)) {
      inverse_pivot_.resize(0);
      return false;
    }
    inverse_pivot_[i] = 1.0 / pivot;
    lower_ratio_[i] = i > 0 ? a.lower[i] * inverse_pivot_[i] : 0.0;
    previous_ratio = (i + 1 < n) ? a.upper[i] * inverse_pivot_[i] : 0.0;
    upper_ratio_[i] = previous_ratio;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    upper_ratio2_[i] = i + 2 < n ? upper_ratio_[i] * upper_ratio_[i + 1] : 0.0;
  }
  return true;
}

Eigen::VectorXd TridiagonalFactorization::inverse_column(Eigen::Index j) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(size());
  x[j] = 1.0;
  solve_in_place(x);
  return x;
}

void TridiagonalFactorization::solve_in_place(Eigen::VectorXd& b) const {
  forward_in_place(b);
  backward_in_place(b);
}

void TridiagonalFactorization::forward_in_place(Eigen::VectorXd& b) const {
  const Eigen::Index n = inverse_pivot_.size();
  // y_i = b_i/pivot_i − (lower_i/pivot_i)·y_{i−1} rather than (b_i − lower_i·y_{i−1})/pivot_i:
  // the same number up to round-off, but the recurrence through y is one multiply and one
  // subtract instead of three operations, which is what bounds the batched kernel's sweep
  // (core/batched_simulation.cpp does these operations, so its lanes equal this bit for bit).
  b[0] *= inverse_pivot_[0];
  for (Eigen::Index i = 1; i < n; ++i) {
    b[i] = b[i] * inverse_pivot_[i] - lower_ratio_[i] * b[i - 1];
  }
}

void TridiagonalFactorization::backward_in_place(Eigen::VectorXd& y) const {
  // x_i = y_i − c'_i·x_{i+1}, two rows at a time: x_i = (y_i − c'_i·y_{i+1}) + c'_i·c'_{i+1}·x_{i+2}.
  // The same number up to round-off, but x_i depends on x_{i+2}, not x_{i+1}: even and odd
  // rows are two independent recurrences, each one multiply and one add per two rows. The
  // batched kernel's back substitution is bound by this recurrence's latency, and does these
  // operations (core/batched_simulation.cpp), so its lanes equal this bit for bit.
  const Eigen::Index n = inverse_pivot_.size();
  if (n < 2) return;
  double y_next = y[n - 2];  // y_{i+1} as the forward sweep left it
  y[n - 2] -= upper_ratio_[n - 2] * y[n - 1];
  for (Eigen::Index i = n - 3; i >= 0; --i) {
    const double yi = y[i];
    y[i] = (yi - upper_ratio_[i] * y_next) + upper_ratio2_[i] * y[i + 2];
    y_next = yi;
  }
}

}  // namespace impactid
