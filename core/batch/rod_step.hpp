// The rod's implicit step lane by lane (core/methods/implicit_integrator.hpp:
// ImplicitIntegrator::predict and ::step, single wall): each lane's constants, the lanes' arrays
// and step_lanes, which every step kind of core/batch/rod_kernel.cpp is made of. Why and how:
// core/batch/batched_simulation.hpp.
//
// Part of core/batch/rod_kernel.cpp, which includes it after core/batch/kernel_target.hpp, as one
// translation unit with it: so the compiler inlines these functions into the kernel's loops as it
// did when they were one file (the same machine code). It includes only core/batch/ headers: the
// kernel file includes every other header first, before the level's target, so that their functions
// keep the baseline target.
#pragma once

#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

// Each lane's copy of the scalar step's constants, computed by the same expressions
// (ImplicitIntegrator: dt2 * c_.b0 is (Δt·Δt)·b0, c_.b1 * dt2 is b1·(Δt·Δt), …).
struct LaneCoefficients {
  double dt;  // the same in every lane (same_batch), so one register rather than two
  // Each lane's own step, for the composite schemes' first sub-step (γ·Δt, γ per lane): read
  // by step_lanes<…, kLaneStep = true> in place of dt.
  Lanes lane_dt;
  Lanes dt2_b0, dt_g0, af, b1_dt2, g1_dt, minus_am, one_minus_w, w, gap;
  LaneMask mass_term;  // α_m ≠ 0: the scalar step adds −α_m·M·a only then
  // Lanes that start stepping at this sample: set_lane wrote their state as it is (u, v, a),
  // not in the deferred form of the other lanes (see step_lanes).
  LaneMask plain_state;
  // The effective matrix's off-diagonals, the same in every row of the uniform rod: with them the
  // factorisation is one array (the inverse pivots): TridiagonalFactorization::factor's ratios of
  // row i are lower·(1/pivot_i) and upper·(1/pivot_i), products the sweeps form again with the same
  // bits. Three arrays a batch would otherwise stream through the cache at every step.
  Lanes lower, upper;
  // The inverse pivots of rows [tail_begin, n − 1): one value per lane. The pivots of a
  // uniform rod converge geometrically to a fixed point (each lane's own), which double
  // precision reaches exactly after a few rows; simulate_batch finds where every lane has
  // reached it (checked bit for bit, else tail_begin = n − 1). The sweeps then read one array
  // fewer from the cache at every row but the first few and the last.
  Lanes tail_pivot, tail_ratio;  // tail_ratio = upper·tail_pivot, factor's upper ratio
  Lanes tail_lower_ratio;        // lower·tail_pivot, factor's lower ratio
  Lanes tail_ratio2;             // tail_ratio·tail_ratio
  Eigen::Index tail_begin;
};

// The rod's matrices (shared by every lane) and the interleaved [unknown][lane] arrays.
struct LaneArrays {
  Eigen::Index n;
  const Tridiagonal* stiffness;
  const Tridiagonal* damping;
  const Tridiagonal* mass;
  double k_lower, k_diag, k_upper;  // the stiffness's interior row, the same in every row
  double m_lower, m_diag, m_upper;  // the mass's interior row, likewise (for the energy)
  Lanes *u, *v, *a;                 // the state
  Lanes* inverse_pivot;  // each lane's factorisation (rows [tail_begin, n − 1) are tail_pivot)
};

// The end rows of K·x as Tridiagonal::multiply forms them: d·x fused onto the neighbour's
// product. (Interior rows: step_lanes, with the neighbours' products shared.)
template <bool kFirst>
[[gnu::always_inline]] inline Lanes stiffness_end_row(const Diagonals& m, Eigen::Index i,
                                                      const Lanes& prev, const Lanes& cur,
                                                      const Lanes& next) {
  if constexpr (kFirst) return fma(splat(m.diag[i]), cur, splat(m.upper[i]) * next);
  return fma(splat(m.diag[i]), cur, splat(m.lower[i]) * prev);
}

// One implicit step of every lane: ImplicitIntegrator::predict and ::step (single wall), lane
// by lane the same operations. Returns each lane's λ at t + Δt.
//
// Flops per unknown and lane, without damping and α_m (count them in the loops below; an FMA
// is a multiply and an add rounded once). The forward sweep: the deferred update of u and v
// 2 FMA, the predictor u* 1 mul 1 FMA 1 add and v* 1 FMA, the α_f-weighted u 1 FMA, K·u 1 mul
// 1 FMA 1 add (the off-diagonal product shared by two rows), the elimination 1 mul 1 FMA
// (rhs = −K·u's sign is carried by the pivot): 3 mul + 7 FMA + 2 add = 19 flops. The back
// substitution, two rows at a time, 2 FMA. Total 3 mul + 9 FMA + 2 add: 14 instructions,
// 23 flops, 12 of the instructions multiplies or FMAs (which only two of the four vector
// pipes of a Zen 4/5 core execute: the bound of the step). In the first rows only, 1 mul
// each for lower·inverse pivot, upper·inverse pivot and the product of two upper ratios. The
// contact costs a few flops at the last row only (2 divides among them). Damping: +1 mul
// 1 FMA in the predictor and 3 mul 3 add for C·v, plus the sign flip; α_m ≠ 0: 4 mul 2 add
// and a blend.
//
// kPlain: every row holds plain u, v, a (the composite schemes' sub-steps start from such
// states: composite_step_lanes), none the deferred form. kLaneStep: the step is c.lane_dt, one
// per lane (the composite's first sub-step), not c.dt. kExtended (with kPlain: Wilson-θ's
// extended step, wilson_theta_step_lanes): the step reads a from `a_source`, not from
// arrays.a, which only takes the solve (the acceleration at the step's end), and stores no
// predictors but the last row's: arrays.u and .v keep their values in every row but the last
// (the interpolation that follows reads them; the caller restores the last), and the step
// stores 2 vectors per unknown instead of 4.
template <bool kDamping, bool kMassTerm, bool kStartingLanes, bool kPlain = false,
          bool kLaneStep = false, bool kExtended = false>
[[gnu::always_inline]] inline Lanes step_lanes(const LaneArrays& arrays, const LaneCoefficients& c,
                                               const Lanes& lambda,
                                               const Lanes* a_source = nullptr) {
  // A local copy, so that the compiler keeps it in registers: a store through a Lanes pointer
  // (may_alias) could otherwise change it, and every use would reload it. (c must be such a
  // copy too: run_batch's.) Without these copies the step ran many more instructions.
  const LaneArrays x = arrays;
  const Eigen::Index n = x.n, last = n - 1;
  const Diagonals K(*x.stiffness);
  const Diagonals C(kDamping ? *x.damping : *x.stiffness);
  const Diagonals M(*x.mass);
  // K's interior rows are one row (checked by simulate_batch): its three values stay in
  // registers instead of three loads and broadcasts per row.
  const Lanes k_lower = splat(x.k_lower), k_diag = splat(x.k_diag);
  const Lanes dt = kLaneStep ? c.lane_dt : splat(c.dt);
  const Lanes minus_af = -c.af;  // up − α_f·du = fma(−α_f, du, up), as the scalar predict

  // Three arrays per lane. The forward sweep reads u*, v*, a (the previous step's predictors
  // and its new acceleration; plain u, v, a in the last row and in lanes that start now), forms
  // u, v at t, and leaves in their place this step's predictors u*, v* and the forward-swept
  // right-hand side y; the back substitution turns y into a at t + Δt and leaves u*, v* (the
  // last row: u, v). (A separate rhs array, or predictors computed again from u, v, a, made the
  // step slower: stores bound the step about as much as its arithmetic.)
  //
  // The α_f-weighted u, v (kept in registers, three rows at a time), and a for the α_m term.
  // p = k·u_w with k = K's off-diagonal: K is symmetric (lower = upper, checked), so the
  // product that row i + 1 needs for its lower term is the one row i − 1 needs for its upper
  // term; computed once, one multiply per row fewer (the step is bound by its multiplies).
  struct Weighted {
    Lanes u, v, a, p;
  };
  const auto predict = [&]<bool kLastRow>(Eigen::Index i) __attribute__((always_inline)) {
    const Lanes a = kExtended ? a_source[i] : x.a[i];
    WeightedRow weighted;
    if constexpr (kExtended && !kLastRow) {
      // predict_row's operations on plain rows, without its stores (u*, v* are dead here).
      const Lanes du = fma(dt, x.v[i], c.dt2_b0 * a);
      weighted.u = fma(minus_af, du, x.u[i] + du);
      if constexpr (kDamping) weighted.v = fma(minus_af, c.dt_g0 * a, fma(c.dt_g0, a, x.v[i]));
    } else {
      weighted = predict_row < !kLastRow && !kPlain, kStartingLanes,
      kDamping > (c, dt, minus_af, &x.u[i], &x.v[i], a);
    }
    Weighted w;
    w.u = weighted.u;
    w.p = k_lower * w.u;
    if constexpr (kDamping) w.v = weighted.v;
    if constexpr (kMassTerm) w.a = a;
    return w;
  };
  // rhs = −K·u_w − C·v_w − α_m·M·a − (1−w)·λ·e_c, then the forward sweep of the solve.
  Weighted prev{}, cur = predict.template operator()<false>(0), next{};
  Lanes eliminated{};
  // Row i; kNextIsLast: row i + 1 is the last (which holds u, v rather than u*, v*).
  const auto forward = [&]<bool kFirst, bool kLast, bool kNextIsLast = false>(
      Eigen::Index i, const Lanes& pivot, const Lanes& ratio) __attribute__((always_inline)) {
    if constexpr (!kLast) next = predict.template operator()<kNextIsLast>(i + 1);
    // The right-hand side times the pivot. With only K's term in it (no damping, no α_m, not
    // the contact row: the hot loop) the sign of −K·u goes onto the pivot, (−s)·p = s·(−p)
    // exactly, one instruction fewer.
    constexpr bool kStiffnessOnly = !kDamping && !kMassTerm && !kFirst && !kLast;
    Lanes scaled;
    if constexpr (kStiffnessOnly) {
      scaled = (fma(k_diag, cur.u, prev.p) + next.p) * -pivot;
    } else {
      Lanes r;
      if constexpr (kFirst || kLast) {
        r = -stiffness_end_row<kFirst>(K, i, prev.u, cur.u, next.u);
      } else {
        r = -(fma(k_diag, cur.u, prev.p) + next.p);
      }
      if constexpr (kDamping) r = r + -1.0 * row<kFirst, kLast>(C, i, prev.v, cur.v, next.v);
      if constexpr (kMassTerm) {
        r = select(c.mass_term, r + c.minus_am * row<kFirst, kLast>(M, i, prev.a, cur.a, next.a),
                   r);
      }
      if constexpr (kLast) r = r - c.one_minus_w * lambda;
      scaled = r * pivot;
    }
    Lanes r = scaled;
    if constexpr (!kFirst) r = fma(-ratio, eliminated, scaled);
    store(&x.a[i], r);
    eliminated = r;
    prev = cur;
    cur = next;
  };
  const Eigen::Index tail = c.tail_begin;  // 1 <= tail <= last (n >= 2)
  if (last == 1) {
    forward.template operator()<true, false, true>(0, x.inverse_pivot[0], Lanes{});
  } else {
    forward.template operator()<true, false>(0, x.inverse_pivot[0], Lanes{});
    // Rows 1 .. last − 2, then last − 1 (whose next row is the last).
    for (Eigen::Index i = 1; i < std::min(tail, last - 1); ++i) {
      forward.template operator()<false, false>(i, x.inverse_pivot[i],
                                                c.lower * x.inverse_pivot[i]);
    }
    // Two rows per iteration in the two long loops: the scheduler then overlaps one row's
    // recurrence with the next row's independent work a little better (docs/performance.md).
#pragma GCC unroll 2
    for (Eigen::Index i = tail; i < last - 1; ++i) {
      forward.template operator()<false, false>(i, c.tail_pivot, c.tail_lower_ratio);
    }
    const Eigen::Index i = last - 1;
    if (i < tail) {
      forward.template operator()<false, false, true>(i, x.inverse_pivot[i],
                                                      c.lower * x.inverse_pivot[i]);
    } else {
      forward.template operator()<false, false, true>(i, c.tail_pivot, c.tail_lower_ratio);
    }
  }
  forward.template operator()<false, true>(last, x.inverse_pivot[last],
                                           c.lower * x.inverse_pivot[last]);

  // The forward sweep leaves the last unknown final, so the contact test comes first, and the
  // constraint sets that unknown before the back substitution carries it up the rod: the same
  // operations as ImplicitIntegrator::step with the contact dof last. A⁻¹·e_c's last entry is the
  // last inverse pivot, bit for bit (its forward sweep is +0 above the last row and 1·p there).
  const Lanes u_free = fma(c.b1_dt2, x.a[last], x.u[last]);
  const LaneMask closes = greater(u_free, c.gap);
  Lanes new_lambda{};
  if (any_lane(closes)) {
    // Force (w·λ) that moves the contact dof from u_free back onto the wall.
    const Lanes last_influence = x.inverse_pivot[last];
    const Lanes weighted = (u_free - c.gap) / (c.b1_dt2 * last_influence);
    new_lambda = select(closes, weighted / c.w, Lanes{});
    store(&x.a[last], select(closes, x.a[last] - weighted * last_influence, x.a[last]));
  }
  // Back substitution. The update u = u* + b1·Δt²·a, v = v* + g1·Δt·a of every row but the
  // last is deferred to the next step's forward sweep, which reads u*, v* and a anyway: the
  // same operations on the same numbers, so the same bits, but the back substitution then
  // loads and stores one array instead of three. Stores are what bounds the step: it went
  // from 6 to 4 per unknown and register. (The last row is updated here: the contact and the
  // recorded velocity read it.)
  // Two rows at a time, as TridiagonalFactorization::backward_in_place: x_i = (y_i − c'_i·y_{i+1})
  // + c'_i·c'_{i+1}·x_{i+2}, so that even and odd rows are two recurrences (per register), each
  // a multiply and an add per two rows: this loop is bound by the recurrence's latency.
  Lanes x1 = x.a[last];  // x_{i+1}
  store(&x.u[last], fma(c.b1_dt2, x1, x.u[last]));
  store(&x.v[last], fma(c.g1_dt, x1, x.v[last]));
  Lanes x2{};        // x_{i+2}
  Lanes y_next;      // y_{i+1}, as the forward sweep left it
  Lanes ratio_next;  // c'_{i+1}
  {
    const Eigen::Index i = last - 1;
    const Lanes ratio = i >= tail ? c.tail_ratio : c.upper * x.inverse_pivot[i];
    y_next = x.a[i];
    x2 = x1;
    x1 = fma(-ratio, x1, y_next);
    store(&x.a[i], x1);
    ratio_next = ratio;
  }
  const auto backward = [&](Eigen::Index i, const Lanes& ratio, const Lanes& ratio2)
      __attribute__((always_inline)) {
    const Lanes y = x.a[i];
    const Lanes solved = fma(ratio2, x2, fma(-ratio, y_next, y));
    store(&x.a[i], solved);
    y_next = y;
    x2 = x1;
    x1 = solved;
  };
#pragma GCC unroll 2
  for (Eigen::Index i = last - 2; i >= tail; --i) {
    backward(i, c.tail_ratio, c.tail_ratio2);
  }
  for (Eigen::Index i = std::min(tail - 1, last - 2); i >= 0; --i) {
    const Lanes ratio = c.upper * x.inverse_pivot[i];
    backward(i, ratio, ratio * ratio_next);
    ratio_next = ratio;
  }
  // Round-off would leave the node a few ulps off the wall; the constraint is exact.
  x.u[last] = select(greater(new_lambda, Lanes{}), c.gap, x.u[last]);
  return new_lambda;
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
