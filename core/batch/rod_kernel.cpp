#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/batch/batched_kr_alpha.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/model/second_order_system.hpp"

// Last: the level's target for the rest of the file (core/batch/kernel_target.hpp), then the lane
// vocabulary, compiled for the level (kept in this order: clang-format would sort them).
// clang-format off
#include "core/batch/kernel_target.hpp"
#include "core/batch/batch_lanes.hpp"
#include "core/batch/simd_lanes.hpp"
// clang-format on

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

constexpr double kInf = std::numeric_limits<double>::infinity();

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
  // The effective matrix's off-diagonals, the same in every row of the uniform rod: with them
  // the factorisation is one array (the inverse pivots): TridiagonalFactorization::factor's
  // ratios of row i are lower·(1/pivot_i) and upper·(1/pivot_i), products the sweeps form again
  // with the same bits. Three arrays a batch would otherwise stream
  // through the cache at every step.
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
  // copy too: run_batch's.) Without these copies the step ran 2.5 times as many instructions.
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

// The composite schemes' weights of the second sub-step's predictors (CompositeCoefficients),
// per lane: q0, q1 and (q2 − 1)·Δt, as BatheComposite::step forms them.
struct CompositeLanes {
  Lanes q0, q1, q2_minus_1_dt;
};

// Row i of the state at t of lanes whose rows hold u*, v*, a (the deferred form step_lanes
// leaves, with c's coefficients; kStartingLanes: plain in c.plain_state's lanes), as the next
// forward sweep would form it: the same operations, so the same bits. The last row is plain.
template <bool kStartingLanes>
[[gnu::always_inline]] inline void state_row(const LaneArrays& x, const LaneCoefficients& c,
                                             Eigen::Index i, bool last_row, Lanes& u, Lanes& v) {
  u = x.u[i];
  v = x.v[i];
  if (last_row) return;
  const Lanes a = x.a[i];
  const Lanes u_updated = fma(c.b1_dt2, a, u), v_updated = fma(c.g1_dt, a, v);
  u = kStartingLanes ? select(c.plain_state, u, u_updated) : u_updated;
  v = kStartingLanes ? select(c.plain_state, v, v_updated) : v_updated;
}

// One step of the composite schemes (core/methods/bathe_composite.hpp: BatheComposite::step) in
// every lane: `x` holds the state at t in the deferred form of the second sub-step's coefficients
// `second` (plain in its plain_state lanes), `mid` takes the sub-step's state. Lane by lane
// the scalar step's operations:
//   1. mid = state (every row plain: mid_ = state);
//   2. the first sub-step on mid (step_lanes, coefficients `first`, step γ·Δt per lane);
//   3. v* = v + Δt·(q0·a + q1·a_γ), u += Δt·(q0·v + q1·v_γ) + ((q2 − 1)·Δt)·v*, v = v*, in
//      Eigen's order of the scalar expressions (no fused multiply-add: the scalar has none);
//   4. the second sub-step on the state (step_lanes, coefficients `second`; λ at t, as the
//      scalar's state.lambda, which the first sub-step does not change).
// Returns each lane's λ at t + Δt (the second sub-step's).
//
// Flops per unknown and lane (no damping; count them here and in step_lanes): step 1, 2 FMA
// (the deferred update) and 3 stores; each sub-step, step_lanes' 23 flops less the deferred
// update's 2 FMA (its rows are plain): 3 mul 7 FMA 2 add, 19 flops; step 3, the deferred update
// of the state 2 FMA and of v_γ 1 FMA (u_γ's is dead code), then 7 mul and 5 add, and 2
// stores. Total 2·2 + 2·19 + 3·2 + 12 = 60 flops per unknown and step in 41 instructions: 2.6
// times HHT's 23 for two stages (1.3 per stage). Stores, which bound the step: 3 + 4 + 2 + 4 =
// 13 per unknown and register, against HHT's 4. Damping: step_lanes' 9 in each sub-step.
template <bool kDamping, bool kStartingLanes>
[[gnu::always_inline]] inline Lanes composite_step_lanes(
    const LaneArrays& arrays, const LaneArrays& mid_arrays, const LaneCoefficients& first,
    const LaneCoefficients& second, const CompositeLanes& q, const Lanes& lambda) {
  const LaneArrays x = arrays, mid = mid_arrays;  // local copies: see step_lanes
  const Eigen::Index n = x.n, last = n - 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes u, v;
    state_row<kStartingLanes>(x, second, i, i == last, u, v);
    store(&mid.u[i], u);
    store(&mid.v[i], v);
    store(&mid.a[i], x.a[i]);
  }
  step_lanes<kDamping, false, false, true, true>(mid, first, lambda);
  const Lanes dt = splat(second.dt);
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes u, v, u_mid, v_mid;
    state_row<kStartingLanes>(x, second, i, i == last, u, v);
    state_row<false>(mid, first, i, i == last, u_mid, v_mid);
    const Lanes a = x.a[i], a_mid = mid.a[i];
    const Lanes v_star = v + dt * (q.q0 * a + q.q1 * a_mid);
    store(&x.u[i], u + (dt * (q.q0 * v + q.q1 * v_mid) + q.q2_minus_1_dt * v_star));
    store(&x.v[i], v_star);
  }
  return step_lanes<kDamping, false, false, true>(x, second, lambda);
}

// Wilson-θ's constants per lane (core/methods/wilson_theta.hpp, WilsonTheta::step and
// set_gap_offsets), by the scalar expressions: 1/θ, θ³ = (θ·θ)·θ, Q's weight τ·τ/3 and P's
// Δt·Δt·(3 − 1/θ)/6 (τ = θ·Δt, the extended step's lane_dt).
struct WilsonLanes {
  Lanes inverse_theta, theta3, q_weight, p_weight;
};

// One Wilson-θ step (core/methods/wilson_theta.hpp: WilsonTheta::step, the rod's single wall) in
// every lane: `x` holds plain u, v, a at t in every row (this step kind keeps no deferred form),
// `mid` takes the extended step's state, `extended` is the linear-acceleration step over τ = θ·Δt
// (lane_dt; its gap is set here at every step). Lane by lane the scalar step's operations:
//   1. the wall's gap shifted onto the extended step: Q and P at the contact dof,
//      gap' = gap + ((Q + θ³·(gap − P)) − gap) (set_gap_offsets, then the integrator's
//      system.gap + offset);
//   2. the extended step on the state (step_lanes, kExtended: plain rows, step τ per lane, its
//      contact on gap', λ at t as the scalar's mid_.lambda; the scalar steps a copy mid = state,
//      which here only takes the solve a_θ);
//   3. the interpolation back to t + Δt, row by row: a₁ = a₀ + (a_θ − a₀)·(1/θ),
//      u += Δt·v + (Δt·Δt/6)·(2·a₀ + a₁), v += (½·Δt)·(a₀ + a₁), in the scalar loop's order
//      (no fused multiply-add: the scalar has none);
//   4. the node snapped onto the unshifted wall where λ_θ > 0.
// Returns each lane's λ_θ, the reported multiplier.
//
// Flops per unknown and lane (no damping; count them here and in step_lanes): step 2,
// step_lanes on plain rows, 3 mul 7 FMA 2 add = 19 flops (2 stores: the forward-swept rhs and
// the solve); step 3, 1 sub 1 mul 1 add for a₁, 3 mul 3 add for u, 1 add 1 mul 1 add for v:
// 12 flops (3 stores). Total 31 flops per unknown and step in 24 instructions (1.3 times HHT's
// 23 flops in 14), 5 stores per unknown and register against HHT's 4. Step 1 is O(1). Damping:
// step_lanes' 9 (its v predictor is then formed without being stored).
template <bool kDamping>
[[gnu::always_inline]] inline Lanes wilson_theta_step_lanes(
    const LaneArrays& arrays, const LaneArrays& mid_arrays, LaneCoefficients& extended,
    const LaneCoefficients& c, const WilsonLanes& wilson, const Lanes& lambda) {
  const LaneArrays x = arrays, mid = mid_arrays;  // local copies: see step_lanes
  const Eigen::Index n = x.n, last = n - 1;
  const Lanes dt = splat(c.dt), tau = extended.lane_dt;
  const Lanes u_last = x.u[last], v_last = x.v[last];
  {
    const Lanes a = x.a[last];
    const Lanes q = (u_last + tau * v_last) + wilson.q_weight * a;
    const Lanes p = (u_last + dt * v_last) + wilson.p_weight * a;
    extended.gap = c.gap + ((q + wilson.theta3 * (c.gap - p)) - c.gap);
  }
  // The extended step from the state itself (the scalar's copy mid = state is not needed: the
  // step reads u, v, a and writes only the solve, into mid.a, and the last row's u, v, which
  // are put back after it).
  LaneArrays e = x;
  e.a = mid.a;
  e.inverse_pivot = mid.inverse_pivot;
  const Lanes new_lambda =
      step_lanes<kDamping, false, false, true, true, true>(e, extended, lambda, x.a);
  store(&x.u[last], u_last);
  store(&x.v[last], v_last);
  const double dt_value = c.dt;
  const Lanes sixth_dt2 = splat(dt_value * dt_value / 6.0), half_dt = splat(0.5 * dt_value);
  const Lanes two = splat(2.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Lanes a0 = x.a[i];
    const Lanes a1 = a0 + (mid.a[i] - a0) * wilson.inverse_theta;
    store(&x.u[i], x.u[i] + (dt * x.v[i] + sixth_dt2 * (two * a0 + a1)));
    store(&x.v[i], x.v[i] + half_dt * (a0 + a1));
    store(&x.a[i], a1);
  }
  x.u[last] = select(greater(new_lambda, Lanes{}), c.gap, x.u[last]);
  return new_lambda;
}

// Houbolt's three effective matrices per lane (core/methods/houbolt.hpp: the start-up's two steps
// and Houbolt's own), each its step's coefficients and its factorisation's inverse pivots, and the
// two past displacements u_{n−1}, u_{n−2} and the initial velocity v₀ ([unknown][lane] each).
struct HouboltLanes {
  std::array<LaneCoefficients, 3> steps;  // first, second, steady (houbolt_coefficients)
  std::array<Lanes*, 3> pivots;           // their inverse pivots
  Lanes *back1, *back2, *start_velocity;
};

// Lane l takes step `phase`'s coefficients and factorisation (0, 1: the start-up's steps; 2:
// Houbolt's), in c and x.inverse_pivot. O(n), twice per run and lane.
inline void use_houbolt_step(const LaneArrays& x, const HouboltLanes& h, int phase, int l,
                             LaneCoefficients& c) {
  const LaneCoefficients& s = h.steps[static_cast<std::size_t>(phase)];
  for (Lanes LaneCoefficients::*field :
       {&LaneCoefficients::lane_dt, &LaneCoefficients::dt2_b0, &LaneCoefficients::dt_g0,
        &LaneCoefficients::af, &LaneCoefficients::b1_dt2, &LaneCoefficients::g1_dt,
        &LaneCoefficients::minus_am, &LaneCoefficients::one_minus_w, &LaneCoefficients::w,
        &LaneCoefficients::gap, &LaneCoefficients::lower, &LaneCoefficients::upper,
        &LaneCoefficients::tail_pivot, &LaneCoefficients::tail_ratio,
        &LaneCoefficients::tail_lower_ratio, &LaneCoefficients::tail_ratio2}) {
    (c.*field).set(l, (s.*field)[l]);
  }
  c.mass_term.set(l, s.mass_term[l]);
  const Lanes* pivots = h.pivots[static_cast<std::size_t>(phase)];
  for (Eigen::Index i = 0; i < x.n; ++i) x.inverse_pivot[i].set(l, pivots[i][l]);
}

// Houbolt's predictors (core/methods/houbolt.hpp: Houbolt::step before its integrator's step) in
// every lane, written into x as the plain state the step starts from, and the past displacements
// shifted. `x` holds the previous step's deferred form (c: its coefficients; plain in
// c.plain_state's lanes, kStartingLanes); `back1`, `back2` hold u_{n−1}, u_{n−2}. Lane by
// lane, in the scalar expressions' order (no fused multiply-add: the scalar has none):
//   phase 0 (step 1): u, v unchanged; v₀ = v;
//   phase 1 (step 2): u* = ((16·u₁ − 11·u₀) − (6·Δt)·v₀)/5, v* = v₀ + (2·((u* − 2·u₁) + u₀))/Δt;
//   phase 2: u* = ½·((5·u_n − 4·u_{n−1}) + u_{n−2}), v* = ((19·u_n − 26·u_{n−1}) + 7·u_{n−2})/
//            (12·Δt);
// then u = u* − Δt·v*, v = v*. The shift is the same in every phase (u_{n−1} becomes u_{n−2},
// u_n becomes u_{n−1}): `back2` is overwritten with u_n, and the caller swaps the two
// pointers. kStartup: some lane is in phase 0 or 1 (`phase0`, `phase1`); else every lane is in
// phase 2 and only Houbolt's formulas are formed.
//
// Flops per unknown and lane (phase 2, no damping): the deferred update 2 FMA, u* 3 mul 2 add,
// v* 3 mul 2 add 1 divide (12·Δt is formed once), u 1 mul 1 add: 17 flops (a divide among
// them, as the scalar's), 3 stores (u, v, u_n).
template <bool kStartingLanes, bool kStartup>
[[gnu::always_inline]] inline void houbolt_predict_lanes(const LaneArrays& arrays,
                                                         const LaneCoefficients& c,
                                                         const HouboltLanes& h, Lanes* back1,
                                                         Lanes* back2, const LaneMask& phase0,
                                                         const LaneMask& phase1) {
  const LaneArrays x = arrays;  // a local copy: see step_lanes
  Lanes* const v0_row = h.start_velocity;
  const Eigen::Index n = x.n, last = n - 1;
  const double dt_value = c.dt;
  const Lanes dt = splat(dt_value), twelve_dt = splat(12.0 * dt_value);
  const Lanes six_dt = splat(6.0 * dt_value);
  const Lanes half = splat(0.5), two = splat(2.0), five = splat(5.0), four = splat(4.0);
  const Lanes nineteen = splat(19.0), twenty_six = splat(26.0), seven = splat(7.0);
  const Lanes sixteen = splat(16.0), eleven = splat(11.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes un, v;
    state_row<kStartingLanes>(x, c, i, i == last, un, v);
    const Lanes u1 = back1[i], u2 = back2[i];
    Lanes u_star = half * ((five * un - four * u1) + u2);
    Lanes v_star = ((nineteen * un - twenty_six * u1) + seven * u2) / twelve_dt;
    if constexpr (kStartup) {
      // Phase 1: u₀ is back1 (about to become u_{n−2}), u₁ the state's u.
      const Lanes v0 = v0_row[i];
      const Lanes first_u_star = ((sixteen * un - eleven * u1) - six_dt * v0) / five;
      const Lanes first_v_star = v0 + (two * ((first_u_star - two * un) + u1)) / dt;
      u_star = select(phase1, first_u_star, u_star);
      v_star = select(phase1, first_v_star, v_star);
      store(&v0_row[i], select(phase0, v, v0));
      store(&x.u[i], select(phase0, un, u_star - dt * v_star));
      store(&x.v[i], select(phase0, v, v_star));
    } else {
      store(&x.u[i], u_star - dt * v_star);
      store(&x.v[i], v_star);
    }
    store(&back2[i], un);
  }
}

// ½·vᵀMv + ½·uᵀKu of every lane after step_lanes, each form summed in
// Tridiagonal::quadratic_form's order (as SecondOrderSystem::energy). Every row but the last
// holds u*, v*, a: u and v are formed as the next forward sweep will form them, so with the
// same bits. The two sums share one loop: each is a chain of dependent adds, and side by side
// they overlap. The interior rows of K and M are one row each (checked by simulate_batch), held
// in registers: loading and broadcasting six values per row made the energy, checked every
// energy_check_interval steps, a twentieth of the batch's time. kPlain: every row holds plain
// u, v (Wilson-θ's step leaves no deferred form).
template <bool kPlain = false>
[[gnu::always_inline]] inline Lanes lane_energy(const LaneArrays& x, const LaneCoefficients& c) {
  const Eigen::Index n = x.n, last = n - 1;
  struct Row {
    Lanes u, v;
  };
  const auto state = [&](Eigen::Index i) __attribute__((always_inline)) {
    if (kPlain || i == last) return Row{x.u[i], x.v[i]};
    const Lanes a = x.a[i];
    return Row{fma(c.b1_dt2, a, x.u[i]), fma(c.g1_dt, a, x.v[i])};
  };
  const Lanes k_lower = splat(x.k_lower), k_diag = splat(x.k_diag), k_upper = splat(x.k_upper);
  const Lanes m_lower = splat(x.m_lower), m_diag = splat(x.m_diag), m_upper = splat(x.m_upper);
  Lanes kinetic{}, strain{};
  Row prev{}, cur = state(0), next{};
  const auto end_row = [&](Eigen::Index i) __attribute__((always_inline)) {
    if (i + 1 < n) next = state(i + 1);
    kinetic = kinetic + cur.v * quadratic_form_row(*x.mass, i, prev.v, cur.v, next.v);
    strain = strain + cur.u * quadratic_form_row(*x.stiffness, i, prev.u, cur.u, next.u);
    prev = cur;
    cur = next;
  };
  end_row(0);
  for (Eigen::Index i = 1; i < last; ++i) {
    next = state(i + 1);
    kinetic = kinetic + cur.v * ((m_diag * cur.v + m_lower * prev.v) + m_upper * next.v);
    strain = strain + cur.u * ((k_diag * cur.u + k_lower * prev.u) + k_upper * next.u);
    prev = cur;
    cur = next;
  }
  if (last > 0) end_row(last);
  return 0.5 * kinetic + 0.5 * strain;
}

using StepKind = BatchStepKind;
constexpr auto step_kind = batch_step_kind;

struct Batch {
  LaneArrays arrays;
  // The single-step method's; a composite's second sub-step's; Wilson-θ's Δt and wall gap.
  LaneCoefficients coefficients;
  // The composite schemes and Wilson-θ only: the first sub-step's (Wilson-θ: the extended
  // step's) coefficients and its state (arrays: the mid state and that step's factorisation);
  // the composites' predictor weights, Wilson-θ's constants.
  StepKind kind;
  LaneArrays mid;
  LaneCoefficients first;
  CompositeLanes weights;
  WilsonLanes wilson;
  HouboltLanes houbolt;  // Houbolt only
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;
  LaneLoop loop;
};

void set_lane(const LaneArrays& x, int lane, const State* state) {
  set_lane_state(x.u, x.v, x.a, x.n, lane, state);
}

// The batch loop (core/batch/batch_lanes.hpp: run_lanes) with the implicit, composite, Wilson-θ or
// Houbolt step.
template <bool kDamping, bool kMassTerm, StepKind kKind>
[[gnu::always_inline]] inline void run_batch(Batch& b) {
  const LaneArrays& x = b.arrays;
  // A local copy, taken once: the compiler then knows that the step's stores through Lanes
  // pointers (may_alias) cannot change it, and keeps its fields in registers. Referred to in
  // Batch, every field was reloaded after every store; copied at every step (a 2 KB copy) it
  // cost a twentieth of the batch's time.
  LaneCoefficients c = b.coefficients;
  LaneCoefficients first = b.first;  // composite and Wilson-θ only, as the three below
  const CompositeLanes weights = b.weights;
  const WilsonLanes wilson = b.wilson;
  const LaneArrays mid = b.mid;
  // Houbolt only: the past displacements (swapped at every step), each lane's place in the
  // start-up: 0 and 1, its first and second step next; 2, Houbolt's step next, its coefficients
  // still the second step's; 3, Houbolt's step with its own (every lane that is not stepping).
  const HouboltLanes& houbolt = b.houbolt;
  Lanes *back1 = houbolt.back1, *back2 = houbolt.back2;
  std::array<int, kLanes> phase;
  phase.fill(3);
  bool startup = false;
  const Eigen::Index contact = x.n - 1;
  run_lanes(
      b.lanes, b.loop,
      lane_stepper(
          [&](int l) __attribute__((always_inline)) {
            const State& start = b.start[static_cast<std::size_t>(l)];
            set_lane(x, l, &start);
            c.plain_state.set(l, true);
            if constexpr (kKind == StepKind::houbolt) {
              phase[static_cast<std::size_t>(l)] = 0;
              startup = true;
              use_houbolt_step(x, houbolt, 0, l, c);
            }
            return LaneStart{.lambda = start.lambda, .t = start.t};
          },
          [&](bool starting, const Lanes& lambda) __attribute__((always_inline)) {
            Lanes next;
            if constexpr (kKind == StepKind::houbolt) {
              if (startup) {
                LaneMask phase0{}, phase1{};
                for (int l = 0; l < kLanes; ++l) {
                  phase0.set(l, phase[static_cast<std::size_t>(l)] == 0);
                  phase1.set(l, phase[static_cast<std::size_t>(l)] == 1);
                }
                if (starting) {
                  houbolt_predict_lanes<true, true>(x, c, houbolt, back1, back2, phase0, phase1);
                } else {
                  houbolt_predict_lanes<false, true>(x, c, houbolt, back1, back2, phase0, phase1);
                }
                // The state at t is formed (with the previous step's coefficients): lanes in
                // their second step or entering Houbolt's take this step's.
                startup = false;
                for (int l = 0; l < kLanes; ++l) {
                  int& p = phase[static_cast<std::size_t>(l)];
                  if (p == 1 || p == 2) use_houbolt_step(x, houbolt, p, l, c);
                  if (p < 3) ++p;
                  startup = startup || p < 3;
                }
              } else {
                houbolt_predict_lanes<false, false>(x, c, houbolt, back1, back2, LaneMask{},
                                                    LaneMask{});
              }
              std::swap(back1, back2);
              c.plain_state = LaneMask{};
              next = step_lanes<kDamping, false, false, true>(x, c, lambda);
            } else if constexpr (kKind == StepKind::wilson_theta) {  // plain rows
              next = wilson_theta_step_lanes<kDamping>(x, mid, first, c, wilson, lambda);
            } else if constexpr (kKind == StepKind::composite) {
              if (starting) {
                next = composite_step_lanes<kDamping, true>(x, mid, first, c, weights, lambda);
                c.plain_state = LaneMask{};
              } else {
                next = composite_step_lanes<kDamping, false>(x, mid, first, c, weights, lambda);
              }
            } else if (starting) {
              next = step_lanes<kDamping, kMassTerm, true>(x, c, lambda);
              c.plain_state = LaneMask{};
            } else {
              next = step_lanes<kDamping, kMassTerm, false>(x, c, lambda);
            }
            return next;
          },
          [&]() __attribute__((always_inline)) { return x.v[contact]; },
          [&]() __attribute__((always_inline)) {
            return lane_energy<kKind == StepKind::wilson_theta>(x, c);
          },
          [&](int l) __attribute__((always_inline)) {
            set_lane(x, l, nullptr);
            if constexpr (kKind == StepKind::houbolt) {
              set_lane_state(back1, back2, houbolt.start_velocity, x.n, l, nullptr);
            }
          }));
}

// One function per step kind: in one function holding every kind's loops, GCC optimised the
// composite and α_m loops worse once Wilson-θ's kind was added beside them (the figures are in
// the log of commit 827a7c7).
void run_composite_batch(Batch& b) {  // both sub-steps have α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::composite>(b);
  } else {
    run_batch<false, false, StepKind::composite>(b);
  }
}

void run_houbolt_batch(Batch& b) {  // its three steps have α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::houbolt>(b);
  } else {
    run_batch<false, false, StepKind::houbolt>(b);
  }
}

void run_wilson_theta_batch(Batch& b) {  // the extended step: α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::wilson_theta>(b);
  } else {
    run_batch<false, false, StepKind::wilson_theta>(b);
  }
}

void run_single_step_batch(Batch& b) {
  with_kernel_flags(
      b.arrays.damping != nullptr, any_lane(b.coefficients.mass_term),
      [&b]<bool kDamping, bool kMassTerm>() __attribute__((always_inline)) {
        run_batch<kDamping, kMassTerm, StepKind::single_step>(b);
      });
}

// The batch loop. Everything it calls in the step loop is inlined.
void run_batch_any(Batch& b) {
  switch (b.kind) {
    case StepKind::composite:
      return run_composite_batch(b);
    case StepKind::houbolt:
      return run_houbolt_batch(b);
    case StepKind::wilson_theta:
      return run_wilson_theta_batch(b);
    case StepKind::single_step:
      return run_single_step_batch(b);
  }
}

// True when a's off-diagonals are one value each (lower in rows 1..n−1, upper in rows
// 0..n−2), as on a uniform rod: then so are those of any combination of such matrices.
bool uniform_off_diagonals(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  for (Eigen::Index i = 1; i < n; ++i) {
    if (a.lower[i] != a.lower[1] || a.upper[i - 1] != a.upper[0]) return false;
  }
  return true;
}

// The weights of each lane's effective matrix (1 − α_m)·M + (1 − α_f)·b1·Δt²·K [+ (1 − α_f)·
// g1·Δt·C].
struct EffectiveWeights {
  Lanes mass, stiffness, damping;
};

// Every `factored` lane's effective matrix and its factorisation at once: lane by lane the
// operations of Tridiagonal::combined and TridiagonalFactorization::factor, as
// ImplicitIntegrator::initialize does them, so the inverse pivots are the same bits; the
// serial divides of 16 factorisations become those of one. Sets the factorisation's
// coefficients k and the inverse pivots; a lane whose matrix is singular, or every lane when the
// rod is not uniform, is marked failed, taken out of `factored` and does not run. (A composite
// scheme's lanes are factored twice, once per sub-step: into b.first, b.mid.inverse_pivot, then
// into b.coefficients, b.arrays.inverse_pivot.)
void factor_lanes(const SecondOrderSystem& system, std::span<const MethodParams> methods,
                  const EffectiveWeights& w, LaneMask& factored, bool uniform_interior,
                  LaneCoefficients& k, Lanes* inverse_pivot, Batch& b) {
  const Tridiagonal& M = system.mass;
  const Tridiagonal& K = system.stiffness;
  const Tridiagonal& C = system.damping;
  const bool damping = system.has_damping();
  const Eigen::Index n = system.size();
  // Row i of mass.combined(w.mass, stiffness, w.stiffness)[.combined(1, damping, w.damping)].
  const auto effective = [&](const Eigen::VectorXd& m, const Eigen::VectorXd& k,
                             const Eigen::VectorXd& c, Eigen::Index i) {
    Lanes e = w.mass * splat(m[i]) + w.stiffness * splat(k[i]);
    if (damping) e = e + w.damping * splat(c[i]);  // combined(1.0, …): 1·e is e
    return e;
  };
  // The kernel takes one lower and one upper value per lane: checked, not assumed.
  const bool uniform = uniform_interior && uniform_off_diagonals(M) && uniform_off_diagonals(K) &&
                       (!damping || uniform_off_diagonals(C));
  const Lanes lower = effective(M.lower, K.lower, C.lower, 1);
  const Lanes upper = effective(M.upper, K.upper, C.upper, 0);
  std::array<bool, kLanes> singular{};
  Lanes ratio{};
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes pivot = effective(M.diag, K.diag, C.diag, i);
    pivot = i > 0 ? pivot - lower * ratio : pivot - Lanes{};
    const Lanes inverse = splat(1.0) / pivot;
    for (int l = 0; l < kLanes; ++l) {
      singular[l] = singular[l] || pivot[l] == 0.0 || !std::isfinite(pivot[l]);
    }
    store(&inverse_pivot[i], select(factored, inverse, Lanes{}));
    ratio = i + 1 < n ? upper * inverse : Lanes{};
  }
  k.lower = lower;
  k.upper = upper;
  for (int l = 0; l < kLanes; ++l) {
    if (!factored[l]) continue;
    LaneRun& run = b.lanes[static_cast<std::size_t>(l)];
    if (singular[l] || !uniform) {
      run.summary->status = RunStatus::failed;
      run.summary->message =
          !uniform ? "batched kernel: the mass, the stiffness or the damping is not uniform "
                     "along the rod"
                   : std::string(to_string(kind_of(methods[static_cast<std::size_t>(l)]))) +
                         ": singular effective matrix";
      run = LaneRun{};
      factored.set(l, false);
      for (Eigen::Index i = 0; i < n; ++i) inverse_pivot[i].set(l, 0.0);
      continue;
    }
    // The first row from which the pivots of rows up to n − 2 are one value, bit for bit.
    Eigen::Index converged = n - 1;
    while (converged > 1 && inverse_pivot[converged - 1][l] == inverse_pivot[n - 2][l]) {
      --converged;
    }
    const double tail_pivot = n > 2 ? inverse_pivot[n - 2][l] : 0.0;
    const double tail_ratio = upper[l] * tail_pivot;
    k.tail_pivot.set(l, tail_pivot);
    k.tail_ratio.set(l, tail_ratio);
    k.tail_lower_ratio.set(l, lower[l] * tail_pivot);
    k.tail_ratio2.set(l, tail_ratio * tail_ratio);
    k.tail_begin = std::max(k.tail_begin, converged);
  }
}

// Lane l's constants of a step of the ImplicitCoefficients family over dt, and the weights of
// its effective matrix, by ImplicitIntegrator::initialize's and ::predict's expressions.
void set_lane_coefficients(int l, const ImplicitCoefficients& co, double dt, double gap,
                           LaneCoefficients& k, EffectiveWeights& w) {
  w.mass.set(l, 1.0 - co.alpha_m);
  w.stiffness.set(l, (1.0 - co.alpha_f) * co.b1 * dt * dt);
  w.damping.set(l, (1.0 - co.alpha_f) * co.g1 * dt);
  const double dt2 = dt * dt;
  k.lane_dt.set(l, dt);
  k.dt2_b0.set(l, dt2 * co.b0);
  k.dt_g0.set(l, dt * co.g0);
  k.af.set(l, co.alpha_f);
  k.b1_dt2.set(l, co.b1 * dt2);
  k.g1_dt.set(l, co.g1 * dt);
  k.minus_am.set(l, -co.alpha_m);
  k.mass_term.set(l, co.alpha_m != 0.0);
  k.one_minus_w.set(l, 1.0 - co.contact_weight);
  k.w.set(l, co.contact_weight);
  k.gap.set(l, gap);
}

}  // namespace

namespace {

// One sub-batch (at most kLanes runs) of the implicit kinds of step.
void simulate_implicit_sub_batch(std::span<const RodScene> scenes,
                                 std::span<const MethodParams> methods, const RunOptions& options,
                                 std::vector<LaneBlock>& blocks, LaneSpan<State> starts,
                                 LaneSpan<ContactTrace> traces, std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  const SecondOrderSystem system = assemble_rod(scenes[0]);  // gap aside, every lane's
  const Eigen::Index n = system.size();
  const LaneLoop loop = loop_settings(scenes[0], options);
  const double dt = loop.dt;

  // The interleaved arrays: state, inverse pivots; for a composite scheme also the sub-step's
  // state and its factorisation's inverse pivots, for Wilson-θ the extended step's.
  const StepKind kind = step_kind(methods[0]);
  const bool composite = kind == StepKind::composite;
  const bool houbolt = kind == StepKind::houbolt;
  // A second state and factorisation (Houbolt: its three factorisations and past displacements).
  const bool two_steps = kind == StepKind::composite || kind == StepKind::wilson_theta;
  const int arrays = two_steps ? 8 : houbolt ? 10 : 4;
  LaneStorage storage(blocks, arrays, n);
  Batch b{};
  LaneArrays& x = b.arrays;
  x.n = n;
  x.stiffness = &system.stiffness;
  x.damping = system.has_damping() ? &system.damping : nullptr;
  x.mass = &system.mass;
  const Tridiagonal& K = system.stiffness;
  x.k_lower = n > 2 ? K.lower[1] : 0.0;
  x.k_diag = n > 2 ? K.diag[1] : 0.0;
  x.k_upper = n > 2 ? K.upper[1] : 0.0;
  bool uniform_interior = true;
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    uniform_interior = uniform_interior && K.lower[i] == x.k_lower && K.diag[i] == x.k_diag &&
                       K.upper[i] == x.k_upper;
  }
  uniform_interior = uniform_interior && x.k_lower == x.k_upper;  // symmetric: step_lanes
  const Tridiagonal& M = system.mass;
  x.m_lower = n > 2 ? M.lower[1] : 0.0;
  x.m_diag = n > 2 ? M.diag[1] : 0.0;
  x.m_upper = n > 2 ? M.upper[1] : 0.0;
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    uniform_interior = uniform_interior && M.lower[i] == x.m_lower && M.diag[i] == x.m_diag &&
                       M.upper[i] == x.m_upper;
  }
  storage.take({&x.u, &x.v, &x.a, &x.inverse_pivot});
  b.kind = kind;
  if (two_steps) {
    b.mid = x;
    storage.take({&b.mid.u, &b.mid.v, &b.mid.a, &b.mid.inverse_pivot});
  }
  b.start = starts.data();
  b.loop = loop;
  LaneCoefficients& k = b.coefficients;
  k.gap = splat(kInf);  // unused lanes never touch a wall
  k.dt = dt;
  k.tail_begin = 1;  // raised to where the slowest lane's pivots have converged
  LaneCoefficients& first = b.first;
  first.gap = splat(kInf);
  first.dt = dt;  // unused: the first sub-step reads lane_dt
  first.tail_begin = 1;
  HouboltLanes& h = b.houbolt;
  std::array<EffectiveWeights, 3> houbolt_weights{};
  if (houbolt) {
    for (std::size_t p = 0; p < 3; ++p) {
      h.steps[p].gap = splat(kInf);
      h.steps[p].dt = dt;
      h.steps[p].tail_begin = 1;
      h.pivots[p] = storage.take();
    }
    storage.take({&h.back1, &h.back2, &h.start_velocity});
  }
  const HouboltCoefficients houbolt_steps = houbolt_coefficients();

  EffectiveWeights weights{}, first_weights{};
  LaneMask factored{};  // the lanes whose effective matrix is to be factored
  for (int l = 0; l < count; ++l) {
    const RodScene& scene = scenes[static_cast<std::size_t>(l)];
    const MethodParams& method = methods[static_cast<std::size_t>(l)];
    // same_batch: one kind of step per batch.
    assert(step_kind(method) == kind);
    LaneRun& run = b.lanes[static_cast<std::size_t>(l)];
    if (!prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, run)) {
      continue;
    }

    // The weights of the lane's effective matrix, as ImplicitIntegrator::initialize; the
    // matrix and its factorisation follow for every lane at once, below. A composite scheme:
    // BatheComposite::initialize's two integrators, the first over γ·Δt.
    if (composite) {
      const CompositeCoefficients cc = composite_coefficients(method);
      set_lane_coefficients(l, cc.first, cc.gamma * dt, scene.gap, first, first_weights);
      set_lane_coefficients(l, cc.second, dt, scene.gap, k, weights);
      b.weights.q0.set(l, cc.q0);
      b.weights.q1.set(l, cc.q1);
      b.weights.q2_minus_1_dt.set(l, (cc.q2 - 1.0) * dt);
    } else if (const auto* wilson = std::get_if<WilsonThetaParams>(&method)) {
      // WilsonTheta::initialize's extended step over θ·Δt; the sample's step Δt and the wall's
      // gap in k (the extended step's gap is set at every step); set_gap_offsets' constants.
      const WilsonThetaCoefficients wc = wilson_theta_coefficients(*wilson);
      const double theta = wc.theta, tau = theta * dt;
      set_lane_coefficients(l, wc.extended, tau, scene.gap, first, first_weights);
      k.gap.set(l, scene.gap);
      b.wilson.inverse_theta.set(l, 1.0 / theta);
      b.wilson.theta3.set(l, theta * theta * theta);
      b.wilson.q_weight.set(l, tau * tau / 3.0);
      b.wilson.p_weight.set(l, dt * dt * (3.0 - 1.0 / theta) / 6.0);
    } else if (houbolt) {  // Houbolt::initialize's three integrators, all over Δt
      set_lane_coefficients(l, houbolt_steps.first, dt, scene.gap, h.steps[0], houbolt_weights[0]);
      set_lane_coefficients(l, houbolt_steps.second, dt, scene.gap, h.steps[1], houbolt_weights[1]);
      set_lane_coefficients(l, houbolt_steps.steady, dt, scene.gap, h.steps[2], houbolt_weights[2]);
    } else {
      set_lane_coefficients(l, implicit_coefficients(method), dt, scene.gap, k, weights);
    }
    factored.set(l, true);
  }
  if (two_steps) {
    factor_lanes(system, methods, first_weights, factored, uniform_interior, first,
                 b.mid.inverse_pivot, b);
  }
  if (houbolt) {
    // Each lane starts with the first step's coefficients (run_batch); lanes not stepping hold
    // Houbolt's. The tail rows are those where all three factorisations have converged.
    Eigen::Index tail = 1;
    for (std::size_t p = 0; p < 3; ++p) {
      factor_lanes(system, methods, houbolt_weights[p], factored, uniform_interior, h.steps[p],
                   h.pivots[p], b);
      tail = std::max(tail, h.steps[p].tail_begin);
    }
    for (LaneCoefficients& s : h.steps) s.tail_begin = tail;
    k = h.steps[2];
    std::copy_n(h.pivots[2], n, x.inverse_pivot);
  } else if (kind != StepKind::wilson_theta) {  // Wilson-θ: one factorisation, the extended step's
    factor_lanes(system, methods, weights, factored, uniform_interior, k, x.inverse_pivot, b);
  }
  run_batch_any(b);
  finish_lanes(count, start, traces, summaries);
}

}  // namespace

void simulate_rod_lanes(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                        const RunOptions& options, BatchStorage ws,
                        std::span<RunSummary> summaries) {
  if (explicit_batch_kind(methods[0]) != ExplicitBatchKind::none) {
    simulate_explicit_lanes(scenes, methods, options, ws, summaries);
    return;
  }
  if (std::holds_alternative<KrAlphaParams>(methods[0])) {
    simulate_kr_alpha_lanes(scenes, methods, options, ws, summaries);
    return;
  }
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    simulate_implicit_sub_batch(scenes.subspan(first, count), methods.subspan(first, count),
                                options, ws.blocks, sub_batch_part(ws.starts, first),
                                sub_batch_part(ws.traces, first), summaries.subspan(first, count));
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
