#include "core/algebra/tridiagonal.hpp"

#include <cmath>

#include "core/common/function_versions.hpp"

namespace impactid {

namespace {

// The three loops of the implicit step, on plain arrays, each compiled with and without FMA3
// instructions (with_fma_versions, core/common/function_versions.hpp).

// y = A·x (A by its diagonals). Written out rather than y = 0, y += 1·A·x: the same values
// without the two no-op flops per row, which the batched kernel (core/batch/rod_kernel.cpp)
// would have to repeat to stay bit-identical. The diagonal term is fused onto the lower one
// (one rounding fewer), as the kernel does it.
void multiply_rows(const double* lower, const double* diag, const double* upper, Eigen::Index n,
                   const double* x, double* y) {
  if (n == 1) {
    y[0] = diag[0] * x[0];
    return;
  }
  with_fma_versions([&] {
    y[0] = std::fma(diag[0], x[0], upper[0] * x[1]);
    for (Eigen::Index i = 1; i + 1 < n; ++i) {
      y[i] = std::fma(diag[i], x[i], lower[i] * x[i - 1]) + upper[i] * x[i + 1];
    }
    y[n - 1] = std::fma(diag[n - 1], x[n - 1], lower[n - 1] * x[n - 2]);
  });
}

// y_i = b_i/pivot_i − (lower_i/pivot_i)·y_{i−1} rather than (b_i − lower_i·y_{i−1})/pivot_i:
// the same number up to round-off, but the recurrence through y is one fused multiply-add
// (4 cycles) instead of three operations, which is what bounds the batched kernel's sweep
// (core/batch/rod_kernel.cpp does these operations, so its lanes equal this bit for bit).
void forward_sweep(const double* inverse_pivot, const double* lower_ratio, Eigen::Index n,
                   double* b) {
  if (n == 0) return;
  with_fma_versions([&] {
    b[0] *= inverse_pivot[0];
    for (Eigen::Index i = 1; i < n; ++i) {
      b[i] = std::fma(-lower_ratio[i], b[i - 1], b[i] * inverse_pivot[i]);
    }
  });
}

// x_i = y_i − c'_i·x_{i+1}, two rows at a time: x_i = (y_i − c'_i·y_{i+1}) + c'_i·c'_{i+1}·x_{i+2}.
// The same number up to round-off, but x_i depends on x_{i+2}, not x_{i+1}: even and odd
// rows are two independent recurrences, each one fused multiply-add per two rows. The
// batched kernel's back substitution is bound by this recurrence's latency, and does these
// operations (core/batch/rod_kernel.cpp), so its lanes equal this bit for bit.
void backward_sweep(const double* upper_ratio, const double* upper_ratio2, Eigen::Index n,
                    double* y) {
  if (n < 2) return;
  with_fma_versions([&] {
    double y_next = y[n - 2];  // y_{i+1} as the forward sweep left it
    y[n - 2] = std::fma(-upper_ratio[n - 2], y[n - 1], y[n - 2]);
    for (Eigen::Index i = n - 3; i >= 0; --i) {
      const double yi = y[i];
      y[i] = std::fma(upper_ratio2[i], y[i + 2], std::fma(-upper_ratio[i], y_next, yi));
      y_next = yi;
    }
  });
}

}  // namespace

Tridiagonal Tridiagonal::zero(Eigen::Index n) {
  return {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
}

bool Tridiagonal::is_diagonal() const {
  const Eigen::Index n = size();
  if (n <= 1) return true;
  return lower.tail(n - 1).isZero(0.0) && upper.head(n - 1).isZero(0.0);
}

bool Tridiagonal::is_zero() const {
  return is_diagonal() && diag.isZero(0.0);
}

Tridiagonal Tridiagonal::combined(double a, const Tridiagonal& other, double b) const {
  return {a * lower + b * other.lower, a * diag + b * other.diag, a * upper + b * other.upper};
}

void Tridiagonal::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  multiply_rows(lower.data(), diag.data(), upper.data(), size(), x.data(), y.data());
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

void TridiagonalFactorization::forward_in_place(Eigen::VectorXd& b) const {
  forward_sweep(inverse_pivot_.data(), lower_ratio_.data(), inverse_pivot_.size(), b.data());
}

void TridiagonalFactorization::backward_in_place(Eigen::VectorXd& y) const {
  backward_sweep(upper_ratio_.data(), upper_ratio2_.data(), inverse_pivot_.size(), y.data());
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

}  // namespace impactid
