// Kim's two-stage explicit scheme's batched kernel (core/methods/kim_explicit.hpp; why and how:
// core/batch/batched_explicit.hpp): its step lane by lane, as a Scheme of the stage schemes'
// batch (core/batch/explicit_stage.hpp).
//
// Part of core/batch/explicit_kernel.cpp, which includes it after core/batch/kernel_target.hpp:
// the three explicit kernels are one translation unit, so that the compiler inlines their shared
// walk and loop into each kernel as it did when they were one file (the same machine code). It
// includes only core/batch/ headers: the kernel file includes every other header first, before the
// level's target, so that their functions keep the baseline target.
#pragma once

#include "core/batch/explicit_rows.hpp"
#include "core/batch/explicit_stage.hpp"
#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

// What KimExplicit::step reads: the solve's rows, the lanes' arrays and each lane's coefficients
// (its own p).
struct KimRows {
  StageSolveRows solve;
  // The state u, v, a (a₀ through the step); u_p of the next step (KimExplicit's u_next_); the
  // first stage's a_p; the second stage's forward sweep. Between the stages u holds ũ₁ and v ṽ₁.
  Lanes *u, *v, *a, *next, *sub_a, *sweep;
  Lanes gap;
  Lanes dt;  // Δt, ũ₁'s coefficient of v₀
  // KimExplicit::step's pΔt, c.u0·Δt·Δt, s₁, c.v0·Δt, c.vp·Δt, its correct()'s c.cu·Δt·Δt and
  // c.cv·Δt, the divided difference's d0, dp, d1, the scales s_u and s_n of the sample and the
  // next force point, ½·pΔt·pΔt; per lane.
  Lanes first, u0, scale_first, v0, vp, du, dv, d0, dp, d1, scale_sample, scale_next, half_first2;
  // The gap where s_u > 0 (p < ½: the sample's own contact problem is solved), +∞ where not.
  Lanes sample_gap;
};

// The divided difference D = (d0·a₀ + dp·a_p) + d1·a₁ (KimExplicit::divided_difference).
[[gnu::always_inline]] inline Lanes kim_divided_difference(const KimRows& b, const Lanes& a0,
                                                           const Lanes& sub_a, const Lanes& a) {
  return (b.d0 * a0 + b.dp * sub_a) + b.d1 * a;
}

// Stage 1's finish of row i from its solved a_p: ũ₁ = ((u₀ + Δt·v₀) + u0·a₀) + s₁·a_p, the
// contact's −λ_p·M⁻¹e_c on a_p and −(s₁·λ_p)·M⁻¹e_c on ũ₁ (kAnyContact, lanes `closes`), then
// ṽ₁ = (v₀ + v0·a₀) + vp·a_p. ũ₁ and ṽ₁ replace u₀ and v₀.
template <bool kAnyContact>
[[gnu::always_inline]] inline void kim_finish_first(const KimRows& b, const LaneMask& closes,
                                                    const Lanes& lambda, const Lanes& scaled_lambda,
                                                    Eigen::Index i, const Lanes& solved) {
  const Lanes u = b.u[i], v = b.v[i], a = b.a[i];
  Lanes predicted = ((u + b.dt * v) + b.u0 * a) + b.scale_first * solved;
  Lanes sub_a = solved;
  if constexpr (kAnyContact) {
    const Lanes influence = splat(b.solve.influence[i]);
    sub_a = select_bits(closes, solved - lambda * influence, solved);
    predicted = select_bits(closes, predicted - scaled_lambda * influence, predicted);
  }
  store(&b.sub_a[i], sub_a);
  store(&b.u[i], predicted);
  store(&b.v[i], (v + b.v0 * a) + b.vp * sub_a);
}

// The second stage's contact, as KimExplicit::step applies it: the sample's (lanes
// `sample`, λ_s; scales s_u·λ_s) and the next force point's (lanes `next`, λ_n; s_n·λ_n and
// s_u·λ_n). Zero where a lane has none.
struct KimSecondContact {
  LaneMask sample, next;
  Lanes sample_lambda, sample_scaled, next_lambda, next_scaled, next_scaled_sample;
};

// Stage 2's finish of row i from its solved a₁ (a₀, a_p, ũ₁ and ṽ₁ in the row's arrays):
// u₁ = ũ₁ + du·D, v₁ = ṽ₁ + dv·D (correct()); the sample's contact corrects a₁ and u₁ and takes
// v₁ again from the corrected a₁ (correct_velocity()); the next u_p = (u₁ + pΔt·v₁) +
// ½(pΔt)²·a₁; the next force point's contact corrects a₁, u_p and u₁ (by s_u·λ_n) and v₁ again.
// The snaps of the last row are the caller's.
template <bool kAnyContact>
[[gnu::always_inline]] inline void kim_finish_second(const KimRows& b, const KimSecondContact& c,
                                                     Eigen::Index i, const Lanes& solved) {
  const Lanes a0 = b.a[i], sub_a = b.sub_a[i], predicted = b.u[i], v_predicted = b.v[i];
  Lanes a = solved;
  const Lanes d = kim_divided_difference(b, a0, sub_a, a);
  Lanes u = predicted + b.du * d;
  Lanes v = v_predicted + b.dv * d;
  if constexpr (kAnyContact) {
    const Lanes influence = splat(b.solve.influence[i]);
    a = select_bits(c.sample, a - c.sample_lambda * influence, a);
    u = select_bits(c.sample, u - c.sample_scaled * influence, u);
    v = select_bits(c.sample, v_predicted + b.dv * kim_divided_difference(b, a0, sub_a, a), v);
    Lanes next = (u + b.first * v) + b.half_first2 * a;
    a = select_bits(c.next, a - c.next_lambda * influence, a);
    next = select_bits(c.next, next - c.next_scaled * influence, next);
    u = select_bits(c.next, u - c.next_scaled_sample * influence, u);
    v = select_bits(c.next, v_predicted + b.dv * kim_divided_difference(b, a0, sub_a, a), v);
    store(&b.next[i], next);
  } else {
    store(&b.next[i], (u + b.first * v) + b.half_first2 * a);
  }
  store(&b.a[i], a);
  store(&b.u[i], u);
  store(&b.v[i], v);
}

// One step of Kim's scheme in every lane (KimExplicit::step, single wall, Lagrange, no damping;
// its velocity predictor v₀ + pΔt·a₀ feeds only the damping term, so it is not formed). Returns
// λ₁ of the sample t + Δt.
//   Stage 1: a_p from M·a_p = −K·u_p (u_p in `next`); ũ₁ and its contact λ_p =
//     (ũ₁,c − gap)/(s₁·(M⁻¹e_c)_c) where it penetrates, ũ₁,c = gap; ṽ₁.
//   Stage 2: a₁ from M·a₁ = −K·ũ₁; u₁, v₁ (correct()); where s_u > 0 and u₁,c > gap the
//     sample's λ_s, u₁,c = gap, v₁ again; u_p = (u₁ + pΔt·v₁) + ½(pΔt)²·a₁; where u_p,c > gap the
//     next force point's λ_n, u_p,c = gap, u₁ −= (s_u·λ_n)·M⁻¹e_c, v₁ again; λ₁ = λ_s + λ_n.
// As Noh–Bathe's, each stage is a forward pass and a back substitution that finishes every row
// as it is solved; the contacts are decided on the last row first (the forward sweep leaves it
// final, and the finishes of the last row only need its own numbers), by the scalar's
// expressions.
//
// Flops per unknown and lane (no contact; count them in stage_forward and the finishes):
// stage 1, the forward pass 3 mul 3 add/sub 1 FMA, the back substitution 2 FMA, ũ₁ 3 mul 3 add,
// ṽ₁ 2 mul 2 add; stage 2 the same forward pass and back substitution, D 3 mul 2 add, u₁ and
// v₁ 2 mul 2 add, u_p 2 mul 2 add: 18 mul 17 add/sub 6 FMA, 47 flops in 41 instructions a step
// (HHT's: 23 in 14), 20.5 instructions a stage. Stores per unknown and register: 1 + 3 (stage
// 1), 1 + 4 (stage 2), 9 (HHT's: 4). While some lane is in contact a finish also subtracts the
// corrections (stage 1: 2 mul 2 sub 2 blends; stage 2, per contact, 3 mul 3 sub, D and v₁ again,
// 4 blends).
[[gnu::always_inline]] inline Lanes kim_step_lanes(const KimRows& rows,
                                                   const RowFactors& uniform_row) {
  const KimRows b = rows;  // local copies: see cdm_step_lanes
  const RowFactors uniform = uniform_row;
  const Eigen::Index last = b.solve.n - 1;
  const Lanes influence = splat(b.solve.influence[last]);

  // Stage 1: the forward pass from u_p into sub_a; λ_p from the last row's contact-free ũ₁.
  stage_forward(b.solve, uniform, b.next, b.sub_a);
  const Lanes free_first =
      ((b.u[last] + b.dt * b.v[last]) + b.u0 * b.a[last]) + b.scale_first * b.sub_a[last];
  const LaneMask closes_first = greater(free_first, b.gap);
  if (any_lane(closes_first)) {
    const Lanes lambda =
        select_bits(closes_first, (free_first - b.gap) / (b.scale_first * influence), Lanes{});
    const Lanes scaled = b.scale_first * lambda;
    back_substitute(
        b.solve, uniform,
        b.sub_a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          kim_finish_first<true>(b, closes_first, lambda, scaled, i, solved);
        });
    store(&b.u[last], select_bits(closes_first, b.gap, b.u[last]));
  } else {
    back_substitute(
        b.solve, uniform,
        b.sub_a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          kim_finish_first<false>(b, closes_first, Lanes{}, Lanes{}, i, solved);
        });
  }

  // Stage 2: the forward pass from ũ₁ into sweep; the contacts from the last row's numbers, in
  // KimExplicit::step's order and expressions.
  stage_forward(b.solve, uniform, b.u, b.sweep);
  const Lanes a0 = b.a[last], sub_a = b.sub_a[last], v_predicted = b.v[last];
  Lanes a = b.sweep[last];
  Lanes d = kim_divided_difference(b, a0, sub_a, a);
  Lanes u = b.u[last] + b.du * d;
  Lanes v = v_predicted + b.dv * d;
  KimSecondContact c{};
  c.sample = greater(u, b.sample_gap);
  if (any_lane(c.sample)) {
    c.sample_lambda = select_bits(c.sample, (u - b.gap) / (b.scale_sample * influence), Lanes{});
    c.sample_scaled = b.scale_sample * c.sample_lambda;
    a = select_bits(c.sample, a - c.sample_lambda * influence, a);
    u = select_bits(c.sample, b.gap, u);
    v = select_bits(c.sample, v_predicted + b.dv * kim_divided_difference(b, a0, sub_a, a), v);
  }
  Lanes next = (u + b.first * v) + b.half_first2 * a;
  c.next = greater(next, b.gap);
  Lanes lambda = c.sample_lambda;
  if (any_lane(c.next)) {
    c.next_lambda = select_bits(c.next, (next - b.gap) / (b.scale_next * influence), Lanes{});
    c.next_scaled = b.scale_next * c.next_lambda;
    c.next_scaled_sample = b.scale_sample * c.next_lambda;
    next = select_bits(c.next, b.gap, next);
    u = select_bits(c.next, u - c.next_scaled_sample * influence, u);
    lambda = select_bits(c.next, lambda + c.next_lambda, lambda);
  }
  if (any_lane(c.sample) || any_lane(c.next)) {
    back_substitute(
        b.solve, uniform,
        b.sweep, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          kim_finish_second<true>(b, c, i, solved);
        });
    // The last row as the scalar leaves it (its snaps onto the wall).
    store(&b.u[last], u);
    store(&b.next[last], next);
  } else {
    back_substitute(
        b.solve, uniform,
        b.sweep, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          kim_finish_second<false>(b, c, i, solved);
        });
  }
  return lambda;
}

// Kim's scheme for simulate_stage_batch.
struct KimLanes {
  using Params = KimExplicitParams;
  using Stepper = KimExplicit;
  using Rows = KimRows;
  static constexpr const char* kName = "kim-explicit";
  static double critical_omega(double p) { return kim_explicit_critical_omega(p); }
  static constexpr int kArrays = 6;  // Rows' arrays

  static KimExplicitCoefficients coefficients(const Params& params) {
    return kim_explicit_coefficients(params);
  }
  static void set_batch(Rows& rows, LaneStorage& arrays, double dt) {
    rows.sweep = arrays.take();
    rows.sample_gap = splat(kInf);
    rows.dt = splat(dt);
  }
  // KimExplicit::initialize's and ::step's coefficients, by their expressions.
  static void set_lane(Rows& rows, int l, const KimExplicitCoefficients& c, double dt, double gap) {
    const double p = c.p, dt2 = dt * dt;
    const double first = p * dt;
    const double scale_sample = c.cu * c.d1 * dt2;
    rows.first.set(l, first);
    rows.u0.set(l, c.u0 * dt * dt);
    rows.scale_first.set(l, c.up * dt2);
    rows.v0.set(l, c.v0 * dt);
    rows.vp.set(l, c.vp * dt);
    rows.du.set(l, c.cu * dt * dt);
    rows.dv.set(l, c.cv * dt);
    rows.d0.set(l, c.d0);
    rows.dp.set(l, c.dp);
    rows.d1.set(l, c.d1);
    rows.scale_sample.set(l, scale_sample);
    rows.scale_next.set(l, scale_sample + p * c.cv * c.d1 * dt2 + 0.5 * p * p * dt2);
    rows.half_first2.set(l, 0.5 * first * first);
    rows.sample_gap.set(l, scale_sample > 0.0 ? gap : kInf);
    rows.gap.set(l, gap);
  }
  // The arrays a lane's start zeroes besides its state.
  [[gnu::always_inline]] static std::array<Lanes*, 2> stage_arrays(const Rows& rows) {
    return {rows.sub_a, rows.sweep};
  }
  [[gnu::always_inline]] static Lanes step_lanes(const Rows& rows, const RowFactors& uniform) {
    return kim_step_lanes(rows, uniform);
  }
  static void run(StageBatch<Rows>& b);  // the target-cloned loop, below
};
void run_kim_batch(StageBatch<KimRows>& b) {
  run_stage_lanes<KimLanes>(b);
}
void KimLanes::run(StageBatch<Rows>& b) {
  run_kim_batch(b);
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
