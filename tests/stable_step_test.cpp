// The explicit limit's Gershgorin bound (core/contact/stable_step.hpp): exact for the uniform
// lumped rod, an upper bound on a graded mesh, the same for a system given as sparse matrices, and
// no limit certified without a diagonal mass.
#include "core/contact/stable_step.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "test_support.hpp"

namespace impactid {
namespace {

double highest_frequency_squared(const SecondOrderSystem& system) {
  return testing::dense_mode(system, static_cast<int>(system.size()) - 1).omega *
         testing::dense_mode(system, static_cast<int>(system.size()) - 1).omega;
}

// c = h·n = 1 on free_rod(n): the highest mode of the lumped free-free chain is ω = 2c/h = 2n.
TEST(StableStep, ExactForTheUniformLumpedRod) {
  for (int n : {1, 2, 10, 57}) {
    const SecondOrderSystem rod = testing::free_rod(n);
    const double bound = highest_frequency_squared_bound(rod);
    EXPECT_NEAR(bound, 4.0 * n * n, 1e-12 * 4.0 * n * n) << n;
    EXPECT_NEAR(highest_frequency_squared(rod), bound, 1e-9 * bound) << n;
    // Courant 1 (Δt = h/c = 1/n) is within the limit, Courant 1 + 1e-9 is not.
    EXPECT_TRUE(within_explicit_limit(1.0 / n, bound)) << n;
    EXPECT_FALSE(within_explicit_limit((1.0 + 1e-9) / n, bound)) << n;
  }
}

TEST(StableStep, UpperBoundOnAGradedMesh) {
  SecondOrderSystem rod;
  rod.mass = Tridiagonal::zero(9);
  rod.stiffness = Tridiagonal::zero(9);
  rod.damping = Tridiagonal::zero(9);
  for (int e = 0; e < 8; ++e) {  // elements of length 1 + e/4, E = 1 + e, ρ = A = 1
    add_truss_elements(rod, e, 1, 1.0 + 0.25 * e, 1.0 + e, 1.0, 1.0, MassMatrix::lumped);
  }
  const double bound = highest_frequency_squared_bound(rod);
  const double exact = highest_frequency_squared(rod);
  EXPECT_GE(bound, exact);
  EXPECT_LT(bound, 2.0 * exact);  // conservative, not useless
}

TEST(StableStep, SparseSystemGivesTheTridiagonalBound) {
  const SecondOrderSystem rod = testing::free_rod(12);
  SparseSystem sparse;
  sparse.mass = to_sparse(rod.mass);
  sparse.stiffness = to_sparse(rod.stiffness);
  EXPECT_DOUBLE_EQ(highest_frequency_squared_bound(sparse), highest_frequency_squared_bound(rod));
}

TEST(StableStep, NoLimitWithoutADiagonalMass) {
  const SecondOrderSystem consistent = testing::free_rod(10, MassMatrix::consistent);
  EXPECT_EQ(highest_frequency_squared_bound(consistent), std::numeric_limits<double>::infinity());
  EXPECT_FALSE(within_explicit_limit(1e-9, highest_frequency_squared_bound(consistent)));
}

}  // namespace
}  // namespace impactid
