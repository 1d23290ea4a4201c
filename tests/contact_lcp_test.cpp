// The multi-contact complementarity solver against brute-force enumeration of the active sets on
// random small problems, and the termination cases.
#include "core/algebra/contact_lcp.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstring>
#include <random>

namespace impactid {
namespace {

// The solution by trying every active set: the one whose μ_S >= 0 and g off S <= 0. The
// reference does not share code with the solver (Eigen's LDLT per subset).
Eigen::VectorXd brute_force(const Eigen::MatrixXd& d, const Eigen::VectorXd& p) {
  const int m = static_cast<int>(p.size());
  double best_residual = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best = Eigen::VectorXd::Zero(m);
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> s;
    for (int k = 0; k < m; ++k) {
      if (mask & (1 << k)) s.push_back(k);
    }
    Eigen::VectorXd mu = Eigen::VectorXd::Zero(m);
    if (!s.empty()) {
      Eigen::MatrixXd dss(s.size(), s.size());
      Eigen::VectorXd ps(s.size());
      for (std::size_t i = 0; i < s.size(); ++i) {
        ps[i] = p[s[i]];
        for (std::size_t j = 0; j < s.size(); ++j) dss(i, j) = d(s[i], s[j]);
      }
      const Eigen::VectorXd x = dss.ldlt().solve(ps);
      for (std::size_t i = 0; i < s.size(); ++i) mu[s[i]] = x[i];
    }
    const Eigen::VectorXd g = p - d * mu;
    // Worst violation of μ >= 0 and g <= 0: zero for the solution.
    const double residual = std::max(-mu.minCoeff(), g.maxCoeff() > 0 ? g.maxCoeff() : 0.0);
    if (residual < best_residual) {
      best_residual = residual;
      best = mu;
    }
  }
  return best;
}

TEST(ContactLcp, AgreesWithEnumerationOnThousandsOfRandomProblems) {
  std::mt19937 rng(12345);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> size(1, 6);
  int multi_flip = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int m = size(rng);
    Eigen::MatrixXd b(m, m);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) b(i, j) = normal(rng);
    }
    // SPD, sometimes strongly coupled (the interacting contacts of a stiff implicit step).
    Eigen::MatrixXd d = b * b.transpose() + 0.05 * Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd p(m);
    for (int k = 0; k < m; ++k) p[k] = normal(rng);
    Eigen::VectorXd mu(m);
    const int flips = solve_contact_lcp(d.data(), p.data(), m, mu.data());
    if (flips > 0) ++multi_flip;
    const Eigen::VectorXd expected = brute_force(d, p);
    const double scale = 1.0 + expected.cwiseAbs().maxCoeff();
    ASSERT_LE((mu - expected).cwiseAbs().maxCoeff(), 1e-9 * scale) << "trial " << trial;
    // Signorini conditions of the answer itself.
    const Eigen::VectorXd g = p - d * mu;
    ASSERT_GE(mu.minCoeff(), 0.0);
    ASSERT_LE(g.maxCoeff(), 1e-9 * (1.0 + p.cwiseAbs().maxCoeff())) << "trial " << trial;
    for (int k = 0; k < m; ++k) ASSERT_LE(std::abs(mu[k] * g[k]), 1e-9 * scale * scale);
  }
  // The start (the penetrating set) must be wrong often enough for the pivoting to be tested.
  EXPECT_GT(multi_flip, 400);
}

TEST(ContactLcp, NoPenetrationGivesNoForce) {
  const double d[] = {2.0, 0.5, 0.5, 1.0};
  const double p[] = {-1.0, -0.0};
  double mu[2] = {7.0, 7.0};
  EXPECT_EQ(solve_contact_lcp(d, p, 2, mu), 0);
  EXPECT_EQ(mu[0], 0.0);
  EXPECT_EQ(mu[1], 0.0);
}

TEST(ContactLcp, DecoupledConstraintsNeedOneSolve) {
  // A diagonal D (lumped central difference): each force is p/d on its own.
  const double d[] = {4.0, 0.0, 0.0, 2.0};
  const double p[] = {2.0, -3.0};
  double mu[2];
  EXPECT_EQ(solve_contact_lcp(d, p, 2, mu), 0);
  EXPECT_EQ(mu[0], 0.5);
  EXPECT_EQ(mu[1], 0.0);
}

// The O(m) path for a diagonal D gives the general solver's bits (its Cholesky of D_SS reduces
// exactly to (p/√d)/√d, or p/d for one penetrating constraint), for any mix of signs and sizes
// up to a block's or a beam's face of contacts.
TEST(ContactLcp, ADiagonalProblemIsSolvedInLinearTimeToTheSameBits) {
  std::mt19937_64 random(20261128);
  std::uniform_real_distribution<double> positive(1e-3, 1e3), signed_value(-1.0, 1.0);
  for (const int m : {1, 2, 3, 17, 121, 300}) {
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::MatrixXd d = Eigen::MatrixXd::Zero(m, m);
      Eigen::VectorXd p(m);
      for (int k = 0; k < m; ++k) {
        d(k, k) = positive(random);
        // A few penetrating constraints, one, all, or none of them.
        const double share = trial % 4 == 0 ? 1.0 : trial % 4 == 1 ? 0.0 : 0.3;
        p[k] = (signed_value(random) + 1.0) / 2.0 < share ? positive(random) : -positive(random);
      }
      if (trial == 3) p.setConstant(-1.0), p[m / 2] = 2.5;  // exactly one
      ASSERT_TRUE(is_positive_diagonal(d.data(), m));
      ContactLcpWorkspace workspace;
      workspace.resize(m);
      Eigen::VectorXd general(m), fast(m);
      EXPECT_EQ(solve_contact_lcp(d.data(), p.data(), m, general.data(), workspace), 0);
      EXPECT_EQ(solve_diagonal_contact_lcp(d.data(), p.data(), m, fast.data()), 0);
      for (int k = 0; k < m; ++k) {
        ASSERT_EQ(std::memcmp(&general[k], &fast[k], sizeof(double)), 0)
            << "m = " << m << ", trial " << trial << ", k = " << k << ": " << general[k]
            << " vs " << fast[k];
      }
    }
  }
  // Not diagonal: an off-diagonal entry, a zero or negative pivot.
  Eigen::MatrixXd d = Eigen::MatrixXd::Identity(3, 3);
  d(2, 0) = 1e-300;
  EXPECT_FALSE(is_positive_diagonal(d.data(), 3));
  d(2, 0) = 0.0, d(1, 1) = 0.0;
  EXPECT_FALSE(is_positive_diagonal(d.data(), 3));
  d(1, 1) = -1.0;
  EXPECT_FALSE(is_positive_diagonal(d.data(), 3));
}

}  // namespace
}  // namespace impactid
