// The rod's step kinds beyond the single step, lane by lane: the composite schemes' two sub-steps
// (core/methods/bathe_composite.hpp), Wilson-θ's extended step (core/methods/wilson_theta.hpp) and
// Houbolt's predictors (core/methods/houbolt.hpp), each made of core/batch/rod_step.hpp's
// step_lanes; and the lanes' energy after a step.
//
// Part of core/batch/rod_kernel.cpp, which includes it after core/batch/kernel_target.hpp, as one
// translation unit with it: so the compiler inlines these functions into the kernel's loops as it
// did when they were one file (the same machine code). It includes only core/batch/ headers: the
// kernel file includes every other header first, before the level's target, so that their functions
// keep the baseline target.
#pragma once

#include "core/batch/rod_step.hpp"
#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

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
// energy_check_interval steps, a visible share of the batch's time. kPlain: every row holds plain
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

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
