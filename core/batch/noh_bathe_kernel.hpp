// The Noh–Bathe explicit scheme's batched kernel (core/methods/noh_bathe.hpp; why and how:
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

// What NohBatheExplicit::step reads: the solve's rows, the lanes' arrays and each lane's
// coefficients (its own p).
struct NohBatheRows {
  StageSolveRows solve;
  // The state u, v, a; u at the next point of the grid (NohBatheExplicit's u_next_); the
  // sub-step's a_p. Between the sub-steps v holds v_p.
  Lanes *u, *v, *a, *next, *sub_a;
  Lanes gap;
  // NohBatheExplicit::step's pΔt, (1−p)Δt, ½·pΔt, c₁, c₂, w0, wp, w1, per lane.
  Lanes first, second, half_first, scale_first, scale_second, w0, wp, w1;
};

// One step of the Noh–Bathe explicit scheme in every lane (NohBatheExplicit::step, single wall,
// no damping; the velocity predictor it forms feeds only the damping term, so it is not formed).
// Returns λ of the equilibrium at t + Δt.
//   Sub-step 1: a_p from M·a_p = −K·u_next; u_next ← u_next + (1−p)Δt·(v + ½pΔt·a) + c₁·a_p, the
//     contact λ_p = (u_next,c − gap)/(c₁·(M⁻¹e_c)_c) where it penetrates, a_p −= λ_p·M⁻¹e_c,
//     u_next −= (c₁·λ_p)·M⁻¹e_c, u_next,c = gap; v_p = v + ½pΔt·(a + a_p).
//   Sub-step 2: u = u_next, v = (v_p + w0·a) + wp·a_p; a from M·a = −K·u; u_next ← (u + pΔt·v) +
//     c₂·a with the contact as above (c₂, λ); v += w1·a.
// Each sub-step is a forward pass (K·u_next, the forward sweep) and a back substitution that
// finishes each row as it is solved (the contact test needs the last row only, which the
// forward sweep leaves final).
//
// Flops per unknown and lane (no contact; count them in stage_forward and the finishes):
// sub-step 1, the forward pass 3 mul 3 add/sub 1 FMA (K·u with the off-diagonal product shared
// by two rows, 0 − K·u, the sweep), the back substitution 2 FMA, u_next 3 mul 3 add, v_p 1 mul
// 2 add; sub-step 2, the forward pass 2 mul 2 add (v) and 3 mul 3 add 1 FMA, the back
// substitution 2 FMA, u_next 2 mul 2 add, v 1 mul 1 add: 15 mul 16 add/sub 6 FMA, 43 flops in
// 37 instructions a step (HHT's: 23 in 14), 18.5 instructions a stage. Stores per unknown and
// register: 1 + 3 (sub-step 1), 3 + 3 (sub-step 2), 10 (HHT's: 4). While some lane is in
// contact a back substitution also subtracts λ·M⁻¹e_c from a and (c·λ)·M⁻¹e_c from u_next
// (2 mul 2 sub 2 blends).
template <bool kAnyContact>
[[gnu::always_inline]] inline void noh_bathe_finish_first(const NohBatheRows& b,
                                                          const LaneMask& closes,
                                                          const Lanes& lambda,
                                                          const Lanes& scaled_lambda,
                                                          Eigen::Index i, const Lanes& solved) {
  const Lanes v = b.v[i], a = b.a[i];
  Lanes next = (b.next[i] + b.second * (v + b.half_first * a)) + b.scale_first * solved;
  Lanes sub_a = solved;
  if constexpr (kAnyContact) {
    const Lanes influence = splat(b.solve.influence[i]);
    sub_a = select(closes, solved - lambda * influence, solved);
    next = select(closes, next - scaled_lambda * influence, next);
  }
  store(&b.sub_a[i], sub_a);
  store(&b.next[i], next);
  store(&b.v[i], v + b.half_first * (a + sub_a));
}

template <bool kAnyContact>
[[gnu::always_inline]] inline void noh_bathe_finish_second(const NohBatheRows& b,
                                                           const LaneMask& closes,
                                                           const Lanes& lambda,
                                                           const Lanes& scaled_lambda,
                                                           Eigen::Index i, const Lanes& solved) {
  const Lanes v = b.v[i];
  Lanes next = (b.u[i] + b.first * v) + b.scale_second * solved;
  Lanes a = solved;
  if constexpr (kAnyContact) {
    const Lanes influence = splat(b.solve.influence[i]);
    a = select(closes, solved - lambda * influence, solved);
    next = select(closes, next - scaled_lambda * influence, next);
  }
  store(&b.a[i], a);
  store(&b.next[i], next);
  store(&b.v[i], v + b.w1 * a);
}

[[gnu::always_inline]] inline Lanes noh_bathe_step_lanes(const NohBatheRows& rows,
                                                         const RowFactors& uniform_row) {
  const NohBatheRows b = rows;  // local copies: see cdm_step_lanes
  const RowFactors uniform = uniform_row;
  const Eigen::Index last = b.solve.n - 1;
  const Lanes influence = splat(b.solve.influence[last]);

  // Sub-step 1. The contact-free u_next of the last row (as the finish computes it) decides λ_p.
  stage_forward(b.solve, uniform, b.next, b.sub_a);
  const Lanes free_first = (b.next[last] + b.second * (b.v[last] + b.half_first * b.a[last])) +
                           b.scale_first * b.sub_a[last];
  const LaneMask closes_first = greater(free_first, b.gap);
  if (any_lane(closes_first)) {
    const Lanes lambda =
        select(closes_first, (free_first - b.gap) / (b.scale_first * influence), Lanes{});
    const Lanes scaled = b.scale_first * lambda;
    back_substitute(
        b.solve, uniform,
        b.sub_a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          noh_bathe_finish_first<true>(b, closes_first, lambda, scaled, i, solved);
        });
    store(&b.next[last], select(closes_first, b.gap, b.next[last]));
  } else {
    back_substitute(
        b.solve, uniform,
        b.sub_a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          noh_bathe_finish_first<false>(b, closes_first, Lanes{}, Lanes{}, i, solved);
        });
  }

  // Sub-step 2.
  // Each row's state first takes u = u_next and v = v_p + w0·a + wp·a_p (NohBatheExplicit::step's
  // order), reading the old a before the sweep's row (into a) overwrites it.
  stage_forward(
      b.solve, uniform, b.next,
      b.a, [&](Eigen::Index i, const Lanes& u) __attribute__((always_inline)) {
        store(&b.u[i], u);
        store(&b.v[i], (b.v[i] + b.w0 * b.a[i]) + b.wp * b.sub_a[i]);
      });
  const Lanes free_second = (b.u[last] + b.first * b.v[last]) + b.scale_second * b.a[last];
  const LaneMask closes_second = greater(free_second, b.gap);
  Lanes lambda{};
  if (any_lane(closes_second)) {
    lambda = select(closes_second, (free_second - b.gap) / (b.scale_second * influence), Lanes{});
    const Lanes scaled = b.scale_second * lambda;
    back_substitute(
        b.solve, uniform,
        b.a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          noh_bathe_finish_second<true>(b, closes_second, lambda, scaled, i, solved);
        });
    store(&b.next[last], select(closes_second, b.gap, b.next[last]));
  } else {
    back_substitute(
        b.solve, uniform,
        b.a, [&](Eigen::Index i, const Lanes& solved) __attribute__((always_inline)) {
          noh_bathe_finish_second<false>(b, closes_second, Lanes{}, Lanes{}, i, solved);
        });
  }
  return lambda;
}

// The Noh–Bathe scheme for simulate_stage_batch.
struct NohBatheLanes {
  using Params = NohBatheParams;
  using Stepper = NohBatheExplicit;
  using Rows = NohBatheRows;
  static constexpr const char* kName = "noh-bathe";
  static double critical_omega(double p) { return noh_bathe_critical_omega(p); }
  static constexpr int kArrays = 5;  // Rows' arrays

  static NohBatheCoefficients coefficients(const Params& params) {
    return noh_bathe_coefficients(params);
  }
  static void set_batch(Rows& /*rows*/, LaneStorage& /*arrays*/, double /*dt*/) {}
  // NohBatheExplicit::initialize's and ::step's coefficients, by their expressions.
  static void set_lane(Rows& rows, int l, const NohBatheCoefficients& c, double dt, double gap) {
    const double p = c.p;
    const double first = p * dt, second = (1.0 - p) * dt;
    rows.first.set(l, first);
    rows.second.set(l, second);
    rows.half_first.set(l, 0.5 * first);
    rows.scale_first.set(l, 0.5 * (1.0 - p) * dt * dt);
    rows.scale_second.set(l, dt * dt * p * ((1.0 - p) * c.q2 + 0.5 * p));
    rows.w0.set(l, second * c.q0);
    rows.wp.set(l, second * (0.5 + c.q1));
    rows.w1.set(l, second * c.q2);
    rows.gap.set(l, gap);
  }
  // The arrays a lane's start zeroes besides its state.
  [[gnu::always_inline]] static std::array<Lanes*, 1> stage_arrays(const Rows& rows) {
    return {rows.sub_a};
  }
  [[gnu::always_inline]] static Lanes step_lanes(const Rows& rows, const RowFactors& uniform) {
    return noh_bathe_step_lanes(rows, uniform);
  }
  static void run(StageBatch<Rows>& b);  // the target-cloned loop, below
};
void run_noh_bathe_batch(StageBatch<NohBatheRows>& b) {
  run_stage_lanes<NohBatheLanes>(b);
}
void NohBatheLanes::run(StageBatch<Rows>& b) {
  run_noh_bathe_batch(b);
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
