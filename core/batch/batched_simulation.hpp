// Several simulations of one rod advanced together, one per SIMD lane: the implicit step of
// core/methods/implicit_integrator.hpp for kBatchLanes parameter points at once (issue 5, "Speed"),
// and the composite schemes' two sub-steps of core/methods/bathe_composite.hpp, Wilson-θ's extended
// step with its interpolation (core/methods/wilson_theta.hpp) and Houbolt's predictors from its
// past displacements with its start-up (core/methods/houbolt.hpp; issue 19, "Speed").
//
// Why: a single run's step is two tridiagonal sweeps, each a serial recurrence whose latency
// (a multiply, a subtract and a multiply per unknown, ~12 cycles) bounds the scalar path far
// above its arithmetic. Lanes are independent runs, so a vector instruction advances every lane
// of a batch by the same operation, and the recurrence's latency is paid once per batch.
//
// Bit-identical to simulate(): every lane performs the scalar path's operations on its own numbers,
// in the same order, with the same intermediate products (Δt²·b0, b1·Δt², …) and the same fused
// multiply-adds (the scalar path's std::fma; the project builds with -ffp-contract=off, so the
// compiler fuses nothing else), and the per-lane branches of the scalar step (contact active or
// not, α_m = 0 or not) become blends. The fused loops (predictor, K·u and the forward sweep in one
// pass; contact correction and back substitution in another) reorder work across unknowns, never
// the operations on one number. So a lane's RunSummary and trace equal simulate()'s bit for bit
// (tests/batched_simulation_test.cpp), whatever the other lanes do: a lane that goes unstable stops
// and is zeroed while the others continue, lanes may start stepping at different samples (different
// free flights) and end at different ones.
//
// Between steps the arrays hold, in every row but the last, the predictors u*, v* and the new
// a: the update u = u* + b1·Δt²·a, v = v* + g1·Δt·a is deferred to the next forward sweep (the
// same operations, so the same bits), which halves the back substitution's stores.
//
// Per unknown and step (HHT or Newmark with a lumped or consistent mass, no damping, α_m = 0)
// a lane costs 3 multiplies, 9 fused multiply-adds and 2 adds (23 flops in 14 instructions);
// the contact adds a few flops at the contact node only (2 divides among them). Damping adds
// 9, α_m ≠ 0 adds 6 (core/batch/rod_step.hpp counts them at the loop).
//
// The composite schemes (Bathe, ρ∞-Bathe, TR-BDF2: BatheComposite::step) run the same step
// twice per step, each sub-step from plain u, v, a (no deferred update: 19 flops per unknown
// each), the first over γ·Δt with γ per lane, between them the copy of the state for the first
// sub-step and the second's predictors from both states, all in the scalar path's order:
// 60 flops per unknown and step without damping (41 instructions), 2.6 times HHT's for two
// stages, with 13 stores per unknown and register against HHT's 4 (the stores bound the step);
// damping adds 18 (composite_step_lanes counts them).
//
// Wilson-θ (WilsonTheta::step) keeps plain u, v, a in every row: its gap shifted onto the
// extended step (O(1), at the contact dof), the step over θ·Δt (θ per lane) from plain rows
// (19 flops per unknown; it reads the state in place, where the scalar steps a copy, and stores
// only its solve), the interpolation back to t + Δt (12 flops; no fused multiply-add, as the
// scalar has none) and the node snapped onto the wall: 31 flops per unknown and step without
// damping (24 instructions, 1.3 times HHT's), with 5 stores per unknown and register against
// HHT's 4; damping adds 9 (wilson_theta_step_lanes counts them). Its energy is checked on the
// plain state, its reported multiplier is the extended step's, as the scalar path's.
//
// Houbolt (Houbolt::step) keeps plain u, v, a in every row before its step and two past
// displacements: its predictors u* = ½·((5·u_n − 4·u_{n−1}) + u_{n−2}), v* = ((19·u_n −
// 26·u_{n−1}) + 7·u_{n−2})/(12·Δt) written as the plain start u = u* − Δt·v*, v = v* (17 flops
// per unknown with the previous step's deferred update, a divide among them, as the scalar's;
// 3 stores), then the single-step kernel from plain rows (19 flops): 36 flops per unknown and
// step without damping (27 instructions, 1.6 times HHT's), 7 stores per unknown and register
// against HHT's 4; damping adds step_lanes' 9. Each lane has its own place in the start-up
// (lanes start stepping at different samples): a lane's first two steps take the start's
// formulas and effective matrices (their coefficients and inverse pivots copied into the
// lane's, O(n) twice per run), blended lane by lane with Houbolt's while some lane is in them.
// Its energy is checked on the plain state, its reported multiplier is that of the equilibrium
// at t + Δt, as the scalar path's.
//
// What batches (batchable / same_batch): single-step implicit methods, composite schemes,
// Wilson-θ and Houbolt on the single-wall rod scene (no far wall), with Lagrange contact and no
// histories requested; lanes of one batch share the rod (elements, length, material, area, mass
// matrix, damping), the time step and the kind of step (single-step, composite, Wilson-θ or
// Houbolt: a batch steps one), and may differ in the method and its parameters (a composite's γ,
// Wilson's θ too), the gap, the velocity and the end time. Scenes of bodies have their own kernel
// (core/batch/batched_chain.hpp), and so have central difference, Noh–Bathe and Kim's scheme (
// core/batch/batched_explicit.hpp) and KR-α (core/batch/batched_kr_alpha.hpp): simulate_batch hands
// their batches over; everything else (penalty and augmented-Lagrangian contact, damped explicit
// runs) runs through simulate().
//
// Thread safety: one BatchWorkspace per thread; simulate_batch is reentrant.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// Runs per batch. The layout is [unknown][lane] whatever the machine: the kernels are compiled
/// for AVX-512 (a batch is two registers) and AVX2 (four), and the level the processor supports
/// is chosen when the program starts (core/common/kernel_level.hpp), so the default build needs no
/// -march=native; on baseline x86-64 each run of a batch goes through simulate().
inline constexpr int kBatchLanes = 16;

/// Whether a run can go through simulate_batch at all: a single-step implicit method, a
/// composite scheme (Bathe, ρ∞-Bathe, TR-BDF2), Wilson-θ, Houbolt, an explicit method of
/// core/batch/batched_explicit.hpp (explicit_batchable) or KR-α (kr_alpha_batchable), Lagrange
/// contact, a scene the kernel knows (single wall: far_gap unset), no histories.
bool batchable(const RodScene& scene, const MethodParams& method, const RunOptions& options);

/// Whether two batchable runs can share a batch: the same rod and time step, the same run
/// options, and both single-step methods, both composite schemes, both Wilson-θ, both Houbolt or
/// both the same explicit method or both KR-α. They may differ in method and its parameters (a
/// composite's sub-step ratio γ, Wilson's θ too), gap, velocity and end time.
bool same_batch(const RodScene& a, const MethodParams& method_a, const RunOptions& options_a,
                const RodScene& b, const MethodParams& method_b, const RunOptions& options_b);

/// Per-thread storage reused from batch to batch (allocation-free once sized).
/// One unknown's values in every lane of a batch, aligned for one vector load.
struct alignas(sizeof(double) * kBatchLanes) LaneBlock {
  double lane[kBatchLanes];
};

class BatchWorkspace {
 public:
  /// Lane k's trace after simulate_batch, as simulate() leaves it in SimulationWorkspace::trace.
  std::array<ContactTrace, kBatchLanes> traces;

 private:
  friend void simulate_batch(std::span<const RodScene>, std::span<const MethodParams>,
                             const RunOptions&, BatchWorkspace&, std::span<RunSummary>);
  std::vector<LaneBlock> storage_;        // the interleaved [unknown][lane] arrays
  std::array<State, kBatchLanes> start_;  // each lane's state when it starts stepping
  SimulationWorkspace scalar_;            // the baseline level's runs, one at a time
  // The explicit kernel (core/batch/batched_explicit.hpp) uses the same storage.
  friend void simulate_explicit_batch(std::span<const RodScene>, std::span<const MethodParams>,
                                      const RunOptions&, BatchWorkspace&, std::span<RunSummary>);
};

/// Runs scenes[k] with methods[k] for k < scenes.size() (1..kBatchLanes runs, every pair
/// batchable and every scene same_batch with the first; all valid) and writes summaries[k] and
/// workspace.traces[k]: the same numbers simulate() gives for that run. wall_time_s is the
/// batch's time divided by the number of runs in it.
void simulate_batch(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                    const RunOptions& options, BatchWorkspace& workspace,
                    std::span<RunSummary> summaries);

}  // namespace impactid
