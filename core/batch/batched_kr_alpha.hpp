// The KR-α explicit method (core/methods/kr_alpha.hpp) on the rod, kBatchLanes runs at a time, one
// per SIMD lane (issue 19, "Speed"), in the [unknown][lane] layout, vocabulary
// (core/batch/simd_lanes.hpp) and per-lane bookkeeping (core/batch/batch_lanes.hpp) of the other
// kernels; simulate_batch (core/batch/batched_simulation.hpp) hands KR-α's batches over here.
//
// Why: a step is a tridiagonal solve with E, two serial sweeps whose latency bounds a single run
// far above its arithmetic; lanes are independent runs, and a vector instruction advances every
// lane by the same operation.
//
// Bit-identical to simulate(): every lane does KrAlphaExplicit::step's operations on its own
// numbers in the same order, with the same fused multiply-adds (the products' d·x fused onto the
// lower neighbour's product, as multiply_rows in core/algebra/tridiagonal.cpp does, the sweeps' as
// TridiagonalFactorization does them; the project builds with -ffp-contract=off, so nothing else
// is fused), with each lane's own D and factorisation of E (its ρ∞, so its α_m, α_f, β, γ) and the
// step's response to a unit contact force, formed by KrAlphaExplicit::initialize's expressions;
// the start (α1·a₀, the first displacement with the contact at the start, v̂₀) likewise, lane by
// lane at set-up. The energy of the `unstable` test is the scalar's own half-step energy.
//
// The step, per lane (KrAlphaExplicit::step: w₁ = w₀ + E⁻¹·(r − D·w₀), core/methods/kr_alpha.hpp),
// in two passes over the rows:
//   up    r = (0 + (−α_f)·K·u) + (−(1 − α_f))·K·u₁, r − D·w, E's forward sweep into y; it leaves
//         the last row (the contact dof, where the back substitution starts) final, so the
//         contact-free u₂ there and the multiplier λ = (u₂ − gap)/(s·W_cc) are decided before
//         the second pass;
//   down  E's back substitution, w += x, u₂ = (u₁ + Δt·v̂₁) + s·w and, in lanes in contact, the
//         corrections of w and u₂ by λ; then v̂ += Δt·w, the next step's first update, done here
//         (the same operation on the same numbers).
// The mass matrix takes no part in a step (lumped or consistent alike): the acceleration, which
// the scalar stepper reports as M⁻¹·D·w, is not what a batch reports. u₁ = u₂ of the last step is
// a pointer swap, not a copy. The reported velocity v̂ + γΔt·w is formed at the contact dof only,
// the one the trace reads.
//
// Per unknown and step a lane costs (counted at the passes in core/batch/kr_alpha_kernel.cpp): up
// 8 mul 8 add/sub 2 FMA, down 3 mul 4 add 2 FMA: 11 mul + 12 add/sub + 4 FMA, 31 flops in 27
// instructions (HHT's step: 23 in 14), 4 stores per unknown and register (HHT's: 4), two passes
// moving 10 arrays of a row (HHT: two passes, 9). While some lane is in contact the second pass
// also subtracts λ times the step's response to a unit contact force from w and u₂ (2 mul 2 sub
// 2 blends, one array more).
//
// What batches (kr_alpha_batchable, through batchable / same_batch): KR-α with any ρ∞ on an
// undamped rod with a lumped or a consistent mass (damped runs go through simulate()), single
// wall, Lagrange contact (the augmented Lagrangian goes through simulate()), no histories; a batch
// holds KR-α only, its lanes the same rod and time step, each its own gap, velocity, end time and
// ρ∞.
//
// Thread safety: simulate_kr_alpha_batch is reentrant; each batch its own storage.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "core/common/state.hpp"
#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// Whether the KR-α kernel steps this run, given that the scene and options are otherwise
/// batchable (single wall, Lagrange, no histories: batchable() checks those): KR-α on an undamped
/// rod.
bool kr_alpha_batchable(const RodScene& scene, const MethodParams& method);

/// simulate_batch for KR-α runs (every pair batchable, every scene same_batch with the first; all
/// valid), with a BatchWorkspace's storage, start states and traces: summaries[k] and traces[k]
/// are what simulate() gives for scenes[k] with methods[k]. wall_time_s is the batch's time
/// divided by the number of runs in it.
void simulate_kr_alpha_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             std::vector<LaneBlock>& storage,
                             std::array<State, kBatchLanes>& starts,
                             std::array<ContactTrace, kBatchLanes>& traces,
                             std::span<RunSummary> summaries);

}  // namespace impactid
