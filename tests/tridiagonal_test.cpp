// Tridiagonal storage and the Thomas factorisation, checked against Eigen's dense algebra.
#include "core/algebra/tridiagonal.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace impactid {
namespace {

// A random strictly diagonally dominant (non-symmetric) matrix: the class the integrators build.
Tridiagonal random_dominant(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> off(-1.0, 1.0), extra(0.1, 2.0);
  Tridiagonal a = Tridiagonal::zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i > 0) a.lower[i] = off(rng);
    if (i + 1 < n) a.upper[i] = off(rng);
    const double sign = (i % 3 == 0) ? -1.0 : 1.0;  // dominant but not all positive
    a.diag[i] = sign * (std::abs(a.lower[i]) + std::abs(a.upper[i]) + extra(rng));
  }
  return a;
}

Eigen::VectorXd random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-3.0, 3.0);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = d(rng);
  return x;
}

// dense() is the reference every other test here relies on, so check it against hand entries.
TEST(Tridiagonal, DenseCopyPlacesTheDiagonalsAndIgnoresUnusedEnds) {
  Tridiagonal a = Tridiagonal::zero(3);
  a.diag << 1, 2, 3;
  a.lower << 99, 4, 5;   // lower(0) unused
  a.upper << 6, 7, 98;   // upper(2) unused
  Eigen::MatrixXd expected(3, 3);
  expected << 1, 6, 0,
              4, 2, 7,
              0, 5, 3;
  EXPECT_EQ(a.dense(), expected);
  EXPECT_FALSE(a.is_diagonal());
}

// The solver is what every implicit step and every CDM step relies on.
TEST(Tridiagonal, FactorAndSolveMatchEigenDenseLu) {
  // 4 and 5 besides 3: the back substitution pairs rows from the end (two recurrences).
  for (Eigen::Index n : {1, 2, 3, 4, 5, 17, 200}) {
    const Tridiagonal a = random_dominant(n, 7u + static_cast<unsigned>(n));
    const Eigen::VectorXd b = random_vector(n, 11u + static_cast<unsigned>(n));
    const Eigen::VectorXd reference = a.dense().partialPivLu().solve(b);

    TridiagonalFactorization lu;
    ASSERT_TRUE(lu.factor(a)) << "n = " << n;
    EXPECT_EQ(lu.size(), n);
    Eigen::VectorXd x = b;
    lu.solve_in_place(x);
    EXPECT_LE((x - reference).norm(), 1e-13 * reference.norm()) << "n = " << n;
    // Residual, independent of the dense solver's own round-off.
    EXPECT_LE((a.dense() * x - b).norm(), 1e-13 * b.norm()) << "n = " << n;
  }
}

// A factorisation is reused for many right-hand sides; solving must not alter it.
TEST(Tridiagonal, RepeatedSolvesWithOneFactorisationAgree) {
  const Tridiagonal a = random_dominant(9, 3);
  TridiagonalFactorization lu;
  ASSERT_TRUE(lu.factor(a));
  const Eigen::VectorXd b1 = random_vector(9, 1), b2 = random_vector(9, 2);
  Eigen::VectorXd x1 = b1, x2 = b2, x1_again = b1;
  lu.solve_in_place(x1);
  lu.solve_in_place(x2);
  lu.solve_in_place(x1_again);
  EXPECT_EQ(x1, x1_again);
  EXPECT_LE((a.dense() * x2 - b2).norm(), 1e-13 * b2.norm());
}

// inverse_column(j) is the contact solvers' influence vector: the dense inverse's column j.
TEST(Tridiagonal, InverseColumnIsTheDenseInversesColumn) {
  const Tridiagonal a = random_dominant(12, 5);
  TridiagonalFactorization lu;
  ASSERT_TRUE(lu.factor(a));
  const Eigen::MatrixXd inverse = a.dense().inverse();
  for (const Eigen::Index j : {0, 5, 11}) {
    const Eigen::VectorXd column = lu.inverse_column(j);
    EXPECT_LE((column - inverse.col(j)).norm(), 1e-13 * inverse.col(j).norm()) << "j = " << j;
  }
}

// Singular matrices must be reported, not divided by zero (the integrators return `failed`).
TEST(Tridiagonal, FactorReportsZeroAndNonFinitePivots) {
  TridiagonalFactorization lu;
  Tridiagonal first_zero = Tridiagonal::zero(3);
  first_zero.diag << 0, 1, 1;
  EXPECT_FALSE(lu.factor(first_zero));

  // [[1, 1], [1, 1]]: the second pivot is 1 − 1·1 = 0.
  Tridiagonal second_zero = Tridiagonal::zero(2);
  second_zero.diag << 1, 1;
  second_zero.upper << 1, 0;
  second_zero.lower << 0, 1;
  EXPECT_FALSE(lu.factor(second_zero));

  Tridiagonal nan_entry = Tridiagonal::zero(2);
  nan_entry.diag << 1, std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(lu.factor(nan_entry));
}

// multiply/multiply_add are the K·u and M·a products of every step.
TEST(Tridiagonal, MultiplyAndMultiplyAddMatchDenseProduct) {
  for (Eigen::Index n : {1, 2, 5, 31}) {
    const Tridiagonal a = random_dominant(n, 100u + static_cast<unsigned>(n));
    const Eigen::VectorXd x = random_vector(n, 200u + static_cast<unsigned>(n));
    const Eigen::VectorXd y0 = random_vector(n, 300u + static_cast<unsigned>(n));
    const Eigen::VectorXd reference = a.dense() * x;

    Eigen::VectorXd y = y0;  // multiply overwrites whatever was there
    a.multiply(x, y);
    EXPECT_LE((y - reference).norm(), 1e-14 * reference.norm()) << "n = " << n;

    Eigen::VectorXd z = y0;
    a.multiply_add(-2.5, x, z);
    const Eigen::VectorXd z_reference = y0 - 2.5 * reference;
    EXPECT_LE((z - z_reference).norm(), 1e-14 * (y0.norm() + 2.5 * reference.norm()))
        << "n = " << n;
  }
}

// Energies are quadratic forms; a wrong off-diagonal term would go unnoticed elsewhere.
TEST(Tridiagonal, QuadraticFormMatchesDenseAndHandValue) {
  const Tridiagonal a = random_dominant(12, 5);
  const Eigen::VectorXd x = random_vector(12, 6);
  const double reference = x.dot(a.dense() * x);
  EXPECT_NEAR(a.quadratic_form(x), reference, 1e-13 * std::abs(reference) + 1e-13);

  // [[2, -1], [-1, 2]] at x = (1, 2): 2·1 − 1·2 − 2·1 + 2·4 = 6.
  Tridiagonal k = Tridiagonal::zero(2);
  k.diag << 2, 2;
  k.upper << -1, 0;
  k.lower << 0, -1;
  EXPECT_DOUBLE_EQ(k.quadratic_form(Eigen::Vector2d(1, 2)), 6.0);
}

// Effective matrices are built as linear combinations (M + β·Δt²·K, …).
TEST(Tridiagonal, CombinedIsTheLinearCombination) {
  const Tridiagonal a = random_dominant(6, 8), b = random_dominant(6, 9);
  const Eigen::MatrixXd expected = 0.75 * a.dense() - 3.0 * b.dense();
  EXPECT_LE((a.combined(0.75, b, -3.0).dense() - expected).norm(), 1e-14 * expected.norm());
}

// Integrators skip damping terms when C is zero and CDM is explicit when M is diagonal.
TEST(Tridiagonal, DiagonalAndZeroPredicates) {
  Tridiagonal a = Tridiagonal::zero(4);
  EXPECT_TRUE(a.is_zero());
  EXPECT_TRUE(a.is_diagonal());
  a.lower[0] = 5.0;  // unused entry: does not make the matrix non-diagonal
  a.upper[3] = 5.0;
  EXPECT_TRUE(a.is_diagonal());
  a.diag[2] = 1.0;
  EXPECT_TRUE(a.is_diagonal());
  EXPECT_FALSE(a.is_zero());
  a.upper[1] = 1e-300;
  EXPECT_FALSE(a.is_diagonal());
}

}  // namespace
}  // namespace impactid
