// The sparse product of a user's model for a batch of right-hand sides, one per lane: the first
// piece of lanes on sparse systems (issue 37). A model's step is one sparse product (explicit
// methods) or solve (implicit ones), which reads the whole matrix from memory for one vector;
// here each stored entry is read once for kBatchLanes vectors, interleaved [unknown][lane]
// (LaneBlock), which is what a batch of parameter points that share the matrix needs.
//
// Bit for bit, lane by lane, the scalar multiply_add (core/model/sparse_system.hpp): the same
// column-major walk, each entry's product then its sum, in the same order, and the scalar's skip
// of a column whose s·x_j is zero as a blend (skipping is not adding +0.0: −0.0 + 0.0 is +0.0).
// So a lane's numbers do not depend on the other lanes (tests/sparse_lanes_test.cpp).
//
// Compiled once per kernel level (core/batch/kernel_target.hpp) and chosen with the other
// kernels (core/batch/batch_kernels.cpp); on baseline x86-64 a lane-by-lane loop with the same
// operations runs instead.
//
// Thread safety: reentrant.
#pragma once

#include <span>

#include "core/batch/batched_simulation.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// y[i].lane[l] += s·(A·x)[i] with x's lane l, for every lane: multiply_add(a, s, x_l, y_l) of
/// each lane l. x and y have a.cols() and a.rows() blocks and must not overlap.
void multiply_add_lanes(const SparseMatrix& a, double s, std::span<const LaneBlock> x,
                        std::span<LaneBlock> y);

}  // namespace impactid
