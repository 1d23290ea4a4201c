// The relative error of eq. 18, ε = Σ|exact − computed| / Σ|exact|, on hand-worked examples.
#include "metrics/relative_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace impactid {
namespace {

// Eq. 18 is the paper's accuracy indicator ε_p, ε_v; a worked example pins the formula down.
TEST(RelativeError, HandExample) {
  // |1 − 1.5| + |−2 − (−2)| + |3 − 2| = 1.5 over |1| + |−2| + |3| = 6.
  const std::vector<double> exact{1.0, -2.0, 3.0}, computed{1.5, -2.0, 2.0};
  EXPECT_DOUBLE_EQ(relative_error(exact, computed), 0.25);
}

// Absolute values in the denominator: signed exact values (the rebound velocity −v0) must not
// cancel. Here the signed sum of exact values is 0, the absolute sum 4.
TEST(RelativeError, SignsDoNotCancelInTheDenominator) {
  const std::vector<double> exact{2.0, -2.0}, computed{1.0, -1.0};
  EXPECT_DOUBLE_EQ(relative_error(exact, computed), 0.5);
}

// A perfect run must score exactly 0, not round-off.
TEST(RelativeError, ZeroWhenComputedEqualsExact) {
  const std::vector<double> exact{0.0, 0.84, 0.84, 0.0};
  EXPECT_EQ(relative_error(exact, exact), 0.0);
}

// Eq. 18 is undefined without a non-zero exact value: NaN, never 0 or inf.
TEST(RelativeError, NanWhenExactIsAllZero) {
  const std::vector<double> zero{0.0, 0.0, -0.0}, computed{0.1, 0.0, 0.2};
  EXPECT_TRUE(std::isnan(relative_error(zero, computed)));
  EXPECT_TRUE(std::isnan(relative_error(std::vector<double>{}, std::vector<double>{})));
  EXPECT_TRUE(std::isnan(RelativeErrorSum{}.value()));
}

// Not symmetric: the exact signal is the reference.
TEST(RelativeError, ExactIsTheReference) {
  const std::vector<double> a{1.0, 1.0}, b{2.0, 3.0};
  EXPECT_DOUBLE_EQ(relative_error(a, b), 1.5);       // (1 + 2)/2
  EXPECT_DOUBLE_EQ(relative_error(b, a), 3.0 / 5.0);  // (1 + 2)/5
}

// A NaN sample must poison the result rather than be skipped.
TEST(RelativeError, NanSamplePropagates) {
  const std::vector<double> exact{1.0, 1.0}, computed{1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_TRUE(std::isnan(relative_error(exact, computed)));
}

// The streaming sum (used by the indicators) equals the span version, in any chunking.
TEST(RelativeError, StreamingSumMatchesSpanVersion) {
  const std::vector<double> exact{0.0, 0.5, 0.5, 0.5, 0.0, -1.0}, computed{0.1, 0.4, 0.7, 0.5, 0.0, -0.9};
  RelativeErrorSum sum;
  for (std::size_t i = 0; i < exact.size(); ++i) sum.add(exact[i], computed[i]);
  // (0.1 + 0.1 + 0.2 + 0 + 0 + 0.1) / 2.5 = 0.2
  EXPECT_NEAR(sum.value(), 0.2, 1e-15);
  EXPECT_DOUBLE_EQ(sum.value(), relative_error(exact, computed));
}

}  // namespace
}  // namespace impactid
