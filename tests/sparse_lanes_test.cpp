// multiply_add_lanes(): every lane's y equals the scalar multiply_add of that lane's x, bit for
// bit, whatever the other lanes hold: the promise the lanes on sparse systems rest on (issue 37).
// Run again at every kernel level (tests/CMakeLists.txt: kernel_levels.*).
#include "core/batch/sparse_lanes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/common/kernel_level.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A square matrix of `n` columns with about `per_column` entries each, a few stored zeros and a
// negative zero among them; `compressed` false leaves it in Eigen's uncompressed mode (free
// space after each column), which the kernel must walk as well.
SparseMatrix random_matrix(Eigen::Index n, int per_column, std::mt19937_64& random,
                           bool compressed = true) {
  std::uniform_int_distribution<Eigen::Index> row(0, n - 1);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  SparseMatrix a(n, n);
  a.reserve(Eigen::VectorXi::Constant(n, per_column + 2));
  for (Eigen::Index j = 0; j < n; ++j) {
    for (int e = 0; e < per_column; ++e) a.coeffRef(row(random), j) = value(random);
  }
  if (n > 3) {
    a.coeffRef(0, 1) = 0.0;   // a stored zero
    a.coeffRef(2, 3) = -0.0;  // a stored negative zero
  }
  if (compressed) a.makeCompressed();
  return a;
}

// Lanes of every kind a sweep's vectors may hold: ordinary numbers, whole zero columns (all lanes
// skip), zeros in some lanes only, −0.0 (skipped too: −0.0 == 0), NaN and ±inf (never skipped).
std::vector<LaneBlock> random_lanes(Eigen::Index n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<LaneBlock> x(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int l = 0; l < kBatchLanes; ++l) {
      double v = value(random);
      if (i % 7 == 0) v = 0.0;                 // a column every lane skips
      if (i % 5 == 1 && l % 3 == 0) v = 0.0;   // skipped by some lanes
      if (i % 11 == 2 && l % 4 == 1) v = -0.0;
      x[static_cast<std::size_t>(i)].lane[l] = v;
    }
  }
  x[4].lane[5] = kNaN;
  x[6].lane[9] = kInf;
  x[8].lane[9] = -kInf;
  return x;
}

// y's start: numbers, and −0.0 where a skipped column must leave it.
std::vector<LaneBlock> start_lanes(Eigen::Index n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<LaneBlock> y(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int l = 0; l < kBatchLanes; ++l) {
      y[static_cast<std::size_t>(i)].lane[l] = i % 3 == 0 ? -0.0 : value(random);
    }
  }
  return y;
}

Eigen::VectorXd lane(const std::vector<LaneBlock>& blocks, int l) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(blocks.size()));
  for (std::size_t i = 0; i < blocks.size(); ++i) out[static_cast<Eigen::Index>(i)] = blocks[i].lane[l];
  return out;
}

// multiply_add_lanes against multiply_add lane by lane, compared as bits.
void expect_lanes_equal_scalar(const SparseMatrix& a, double s, const std::vector<LaneBlock>& x,
                               const std::vector<LaneBlock>& y0, const std::string& what) {
  std::vector<LaneBlock> y = y0;
  multiply_add_lanes(a, s, x, y);
  for (int l = 0; l < kBatchLanes; ++l) {
    Eigen::VectorXd expected = lane(y0, l);
    multiply_add(a, s, lane(x, l), expected);
    const Eigen::VectorXd got = lane(y, l);
    for (Eigen::Index i = 0; i < expected.size(); ++i) {
      ASSERT_EQ(std::memcmp(&got[i], &expected[i], sizeof(double)), 0)
          << what << ", kernels " << to_string(kernel_level()) << ": lane " << l << ", row " << i
          << ": " << got[i] << " vs " << expected[i];
    }
  }
}

TEST(SparseLanes, EveryLaneIsTheScalarProductBitForBit) {
  std::mt19937_64 random(20261128);
  for (const Eigen::Index n : {1, 9, 300}) {
    const SparseMatrix a = random_matrix(n, 6, random);
    const std::vector<LaneBlock> x = random_lanes(n < 9 ? 9 : n, random);
    const std::vector<LaneBlock> xs(x.begin(), x.begin() + n);
    const std::vector<LaneBlock> y0 = start_lanes(n, random);
    for (const double s : {1.0, -1.0, 0.37, -0.0}) {
      expect_lanes_equal_scalar(a, s, xs, y0, "n " + std::to_string(n) + ", s " + std::to_string(s));
    }
  }
}

TEST(SparseLanes, UncompressedStorageToo) {
  std::mt19937_64 random(7);
  const SparseMatrix a = random_matrix(64, 5, random, false);
  ASSERT_FALSE(a.isCompressed());
  expect_lanes_equal_scalar(a, -1.0, random_lanes(64, random), start_lanes(64, random),
                            "uncompressed");
}

// A lane's result does not depend on what the others hold: lane 0 with the others zero, NaN or
// different numbers gives the same bits.
TEST(SparseLanes, ALaneIgnoresTheOthers) {
  std::mt19937_64 random(11);
  const Eigen::Index n = 120;
  const SparseMatrix a = random_matrix(n, 8, random);
  std::vector<LaneBlock> x = random_lanes(n, random);
  const std::vector<LaneBlock> y0 = start_lanes(n, random);
  std::vector<LaneBlock> alone = y0;
  multiply_add_lanes(a, 1.0, x, alone);
  for (LaneBlock& b : x) {
    for (int l = 1; l < kBatchLanes; ++l) b.lane[l] = l % 2 ? kNaN : 0.0;
  }
  std::vector<LaneBlock> others = y0;
  multiply_add_lanes(a, 1.0, x, others);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(std::memcmp(&alone[k].lane[0], &others[k].lane[0], sizeof(double)), 0) << i;
  }
}

}  // namespace
}  // namespace impactid
