// The tridiagonal walk shared by the rod's explicit kernels (central difference's, Noh–Bathe's,
// Kim's): one row's factors, the forward pass down the rod and the back substitution up it (the
// operations of Tridiagonal::multiply and TridiagonalFactorization, in their order), and the rows
// that are held in registers.
//
// Part of core/batch/explicit_kernel.cpp, which includes it after core/batch/kernel_target.hpp:
// the three explicit kernels are one translation unit, so that the compiler inlines their shared
// walk and loop into each kernel as it did when they were one file (the same machine code). It
// includes only core/batch/ headers: the kernel file includes every other header first, before the
// level's target, so that their functions keep the baseline target.
#pragma once

#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

// `mask ? a : b` lane by lane as a blend of the bits (a mask lane is all ones or all zeros, as
// greater() sets it): the same bits as simd::select. In Kim's kernel GCC 12 lowered
// simd::select's vector conditional lane by lane, a compare and a branch per lane, where its
// masks are the second stage's contacts (docs/performance.md); the blend of the bits is one
// instruction per register (vpternlogq).
[[gnu::always_inline]] inline Register select_bits(const MaskRegister& mask, const Register& a,
                                                   const Register& b) {
  return (Register)((mask & (MaskRegister)a) | (~mask & (MaskRegister)b));
}
[[gnu::always_inline]] inline Lanes select_bits(const LaneMask& mask, const Lanes& a,
                                                const Lanes& b) {
  Lanes out;
  for_each_register([&](auto k) __attribute__((always_inline)) {
    out.r[k] = select_bits(mask.r[k], a.r[k], b.r[k]);
  });
  return out;
}

// One row's numbers of an explicit step, the same in every lane: M's and K's diagonal entries and
// the factorisation of the left-hand matrix (M/Δt² for central difference, M for the stage
// schemes: TridiagonalFactorization's 1/pivot, −lower/pivot, −upper/pivot and the product of two
// upper ratios, negated where the sweeps negate them).
struct RowFactors {
  Lanes mass_diag, stiffness_diag, inverse_pivot, minus_lower_ratio, minus_upper_ratio,
      upper_ratio2;
};

// The forward pass's walk down the rod, shared by the three kernels: row(i, f) for the rows
// 0 … n − 1 in order, with kFirst and kLast template flags, each row's factors `f` read from the
// rows' arrays (row_factors(b, i)) except on the uniform rows, whose factors `uniform` the caller
// holds in registers, two rows an iteration there.
template <class Rows, class Row>
[[gnu::always_inline]] inline void forward_rows(const Rows& b, const RowFactors& uniform,
                                                Row&& row) {
  const Eigen::Index last = b.n - 1;
  row.template operator()<true, false>(0, row_factors(b, 0));
  const Eigen::Index uniform_begin = std::max<Eigen::Index>(b.uniform_begin, 1);
  const Eigen::Index uniform_end = std::min(b.uniform_end, last);
  Eigen::Index i = 1;
  for (; i < std::min(uniform_begin, last); ++i) {
    row.template operator()<false, false>(i, row_factors(b, i));
  }
#pragma GCC unroll 2
  for (; i < uniform_end; ++i) row.template operator()<false, false>(i, uniform);
  for (; i < last; ++i) row.template operator()<false, false>(i, row_factors(b, i));
  row.template operator()<false, true>(last, row_factors(b, last));
}

// Row i of K·u (Tridiagonal::multiply: (l·u₋ + d·u) + u·u₊, the end rows without the missing
// term), from the off-diagonal products q = k·u of its neighbours, each shared by two rows.
template <bool kFirst, bool kLast>
[[gnu::always_inline]] inline Lanes stiffness_row(const Lanes& diag, const Lanes& prev_q,
                                                  const Lanes& u, const Lanes& next_q) {
  if constexpr (kFirst) {
    return diag * u + next_q;
  } else if constexpr (kLast) {
    return prev_q + diag * u;
  } else {
    return (prev_q + diag * u) + next_q;
  }
}

// Row i of the forward sweep (TridiagonalFactorization's): y_i·(1/pivot_i) −
// (l_i/pivot_i)·y_{i−1}, one FMA, stored at *out; `eliminated` carries y_{i−1} to the next row.
template <bool kFirst>
[[gnu::always_inline]] inline void sweep_row(const RowFactors& f, const Lanes& rhs,
                                             Lanes& eliminated, Lanes* out) {
  Lanes r = rhs * f.inverse_pivot;
  if constexpr (!kFirst) r = fma(f.minus_lower_ratio, eliminated, r);
  store(out, r);
  eliminated = r;
}

// The back substitution (TridiagonalFactorization::backward_in_place) of the forward sweep's y in
// y_rows, shared by the three kernels: x_{n−2} = y_{n−2} − c'·x_{n−1}, then
// x_i = (y_i − c'_i·y_{i+1}) + c'_i·c'_{i+1}·x_{i+2}, calling finish(i, x_i) with each solved x_i,
// the last row's first, then up the rod. The solved values carry the recurrence; finish stores
// what the row's step makes of them (it may overwrite y_i: each y is read before its finish).
template <class Rows, class Finish>
[[gnu::always_inline]] inline void back_substitute(const Rows& b, const RowFactors& uniform,
                                                   const Lanes* y_rows, Finish&& finish) {
  const Eigen::Index last = b.n - 1;
  Lanes x1 = y_rows[last];  // x_{i+1}
  finish(last, x1);
  Lanes x2{};    // x_{i+2}
  Lanes y_next;  // y_{i+1}
  {
    const Eigen::Index i = last - 1;
    y_next = y_rows[i];
    x2 = x1;
    x1 = fma(-splat(b.upper_ratio[i]), x1, y_next);
    finish(i, x1);
  }
  const auto backward = [&](Eigen::Index i, const Lanes& minus_ratio, const Lanes& ratio2)
      __attribute__((always_inline)) {
    const Lanes y = y_rows[i];
    const Lanes solved = fma(ratio2, x2, fma(minus_ratio, y_next, y));
    finish(i, solved);
    y_next = y;
    x2 = x1;
    x1 = solved;
  };
  const Eigen::Index uniform_last = b.uniform_end - 1;  // rows above it are generic
  Eigen::Index i = last - 2;
  for (; i > uniform_last; --i) {
    const RowFactors f = row_factors(b, i);
    backward(i, f.minus_upper_ratio, f.upper_ratio2);
  }
#pragma GCC unroll 2
  for (; i >= b.uniform_begin; --i) backward(i, uniform.minus_upper_ratio, uniform.upper_ratio2);
  for (; i >= 0; --i) {
    const RowFactors f = row_factors(b, i);
    backward(i, f.minus_upper_ratio, f.upper_ratio2);
  }
}

// The rows [begin, end) of one value, which the kernels hold in registers: ending before the last
// two (whose upper_ratio2 is 0 and whose diagonal is the end's), beginning where every array of
// `per_row` has reached the value of the row before them (a lumped mass: row 1; a consistent one:
// where its pivots have converged). Bit for bit: the kernels' rows are checked, not assumed.
struct UniformRows {
  Eigen::Index begin, end;
};
UniformRows uniform_rows(Eigen::Index n, std::initializer_list<const double*> per_row) {
  UniformRows rows;
  rows.end = std::max<Eigen::Index>(n - 2, 1);
  const Eigen::Index ref = rows.end - 1;
  const auto same_row = [&](Eigen::Index i) {
    return std::all_of(per_row.begin(), per_row.end(),
                       [&](const double* values) { return values[i] == values[ref]; });
  };
  rows.begin = ref >= 1 ? ref : rows.end;
  while (rows.begin > 1 && same_row(rows.begin - 1)) --rows.begin;
  return rows;
}

// upper_ratio_i·upper_ratio_{i+1}, as TridiagonalFactorization::factor forms it (0 on the last
// two rows).
Eigen::VectorXd upper_ratio_products(const Eigen::VectorXd& upper_ratio) {
  const Eigen::Index n = upper_ratio.size();
  Eigen::VectorXd products(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    products[i] = i + 2 < n ? upper_ratio[i] * upper_ratio[i + 1] : 0.0;
  }
  return products;
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
