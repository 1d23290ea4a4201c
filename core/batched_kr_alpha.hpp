// The KR-α explicit method (core/kr_alpha.hpp) on the rod, kBatchLanes runs at a time, one per SIMD
// lane (issue 19, "Speed"), in the [unknown][lane] layout, vocabulary (core/simd_lanes.hpp) and
// per-lane bookkeeping (core/batch_lanes.hpp) of the other kernels; simulate_batch
// (core/batched_simulation.hpp) hands KR-α's batches over here.
//
// Why: a step is three tridiagonal solves (M, E, D), six serial sweeps whose latency bounds a
// single run far above its arithmetic; lanes are independent runs, and a vector instruction
// advances every lane by the same operation.
//
// Bit-identical to simulate(): every lane does KrAlphaExplicit::step's operations on its own
// numbers in the same order, with the same fused multiply-adds (Tridiagonal::multiply's d·x fused
// onto the lower neighbour's product, the sweeps' as TridiagonalFactorization does them; the
// project builds with -ffp-contract=off, so nothing else is fused), with each lane's own
// factorisations of D and E (its ρ∞, so its α_m, α_f, β, γ), M's, and the step's responses to a
// unit contact force, formed by KrAlphaExplicit::initialize's expressions; the start (α1·a₀, the
// first displacement with the contact at the start, v̂₀) likewise, lane by lane at set-up. The
// energy of the `unstable` test is the scalar's own half-step energy.
//
// The step, per lane (KrAlphaExplicit::step), in passes over the rows, each one sweep with the
// products and vector work that can ride on it:
//   A (up)   r = (0 + (−α_f)·K·u) + (−(1 − α_f))·K·u₁, M's forward sweep;
//   B (down) M's back substitution, r − a, D·(r − a) row by row as its neighbours are solved;
//   C (up)   E's forward sweep;
//   D (down) E's back substitution, a += x;
//   E (up)   w = M·a row by row, D's forward sweep; it leaves the last row (the contact dof)
//            final, so the contact-free u₂ there and the multiplier λ = (u₂ − gap)/(s·W_cc) are
//            decided before F;
//   F (down) D's back substitution (w = α1·a), u₂ = (u₁ + Δt·v̂₁) + s·w and, in lanes in contact,
//            the corrections of a, w and u₂ by λ; then v̂ += Δt·w, the next step's first update,
//            done here so that w is never stored (the same operation on the same numbers).
// On a lumped mass (the paper's rod, and every shipped plan's) A, B and C are one pass upwards:
// M's factorisation has zero ratios, so its sweeps give r_i·(1/m_i) bit for bit whenever that is
// finite (KrRows::lumped_mass says why), and D·(r − a) and E's forward sweep follow one row
// behind; a step where some r_i·(1/m_i) is not finite (then neither is the sweep's last row) does
// A, B and C instead. u₁ = u₂ of the
// last step is a pointer swap, not a copy. The reported velocity v̂ + γΔt·w is formed at the
// contact dof only, the one the trace reads.
//
// Per unknown and step a lane costs (counted at the passes in core/batched_kr_alpha.cpp), on a
// lumped mass: ABC 9 mul 8 add/sub 2 FMA, D 1 add 2 FMA, E 2 mul 1 add 2 FMA, F 3 mul 3 add
// 2 FMA: 14 mul + 13 add/sub + 8 FMA, 43 flops in 35 instructions (HHT's step: 23 in 14), 5 stores
// per unknown and register (HHT's: 4), four passes moving 14 arrays of a row (HHT: two passes, 9).
// On a consistent mass: A 7 mul 6 add 1 FMA, B 1 mul 2 add/sub 3 FMA, C 1 mul 1 FMA, then D, E, F:
// 49 flops in 38 instructions, six passes, 18 arrays. While some lane is in contact F also
// subtracts λ times the step's responses to a unit contact force from a, w and u₂ (3 mul 3 sub 3
// blends, one store more).
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

#include "core/batched_simulation.hpp"
#include "core/method.hpp"
#include "core/rod_scene.hpp"
#include "core/simulation.hpp"
#include "core/state.hpp"

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
