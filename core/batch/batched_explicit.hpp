// The rod's explicit methods advanced kBatchLanes runs at a time, one per SIMD lane (issue 19,
// "Speed"): central difference (core/methods/central_difference.hpp), the Noh–Bathe explicit scheme
// (core/methods/noh_bathe.hpp) and Kim's two-stage explicit scheme (core/methods/kim_explicit.hpp),
// in the same [unknown][lane] layout, vocabulary (core/batch/simd_lanes.hpp) and per-lane
// bookkeeping (core/batch/batch_lanes.hpp) as the implicit kernel
// (core/batch/batched_simulation.hpp), which hands these batches over here.
//
// Why: central difference's step is a product with M and K and a solve with M/Δt² (one
// tridiagonal factorisation, even for a lumped mass), Noh–Bathe's and Kim's two products with K
// and two solves with M: sweeps whose serial recurrences bound a single run far above its
// arithmetic, as they bound the implicit step. Lanes are independent runs; a vector instruction
// advances every lane by the same operation.
//
// Bit-identical to simulate(): every lane does CentralDifference::step's operations on its own
// numbers in the same order, with the same fused multiply-adds (Tridiagonal::multiply's d·x fused
// onto the lower neighbour's product, the sweeps' as TridiagonalFactorization does them; the
// project builds with -ffp-contract=off, so nothing else is fused), and with the same factorisation
// of M/Δt² and A⁻¹·e_c, formed by CentralDifference::initialize's expressions. Each lane starts as
// simulate() does: initialize's Taylor start u₋ = u₀ − Δt·v₀ + ½Δt²·a₀, then one step that gives
// the state at the start (not a sample) and u one step ahead (the kernel's step, every lane from
// its own start at once, before the loop); the lane steps on from there when its free flight ends.
// The products with zero off-diagonals of a lumped mass are done as the scalar step does them, not
// skipped: a zero times an overflowed value is NaN, not zero, and an unstable lane must stop as the
// scalar run stops. The energy of the `unstable` test is the scalar's: central_difference_energy
// within the explicit limit certified by core/contact/stable_step.hpp (the same for every lane: one
// rod, one step), ½vᵀMv + ½uᵀKu of the reported velocity above it. So each lane's RunSummary and
// trace equal simulate()'s bit for bit (tests/batched_explicit_test.cpp), whatever the other lanes
// do: a lane above its stable step stops as unstable, and is zeroed, while the others go on.
//
// Noh–Bathe likewise: NohBatheExplicit::step's operations lane by lane (each lane its own p, so
// its own sub-step coefficients), with M's factorisation and M⁻¹·e_c; each sub-step's contact
// (a forward increment) decided on the last row, which the forward sweep leaves final, and its
// correction of a and u_next fused into the back substitution. The start is
// NohBatheExplicit::initialize's, lane by lane at set-up (its u_p, the contact at the start, the
// stable step and the warning above it, as simulate() reports them); the energy is the plain one.
//
// Kim's scheme likewise: KimExplicit::step's operations lane by lane (each lane its own p), with
// M's factorisation and M⁻¹·e_c; its three contacts (ũ₁ at stage 1; the sample, where p < ½, and
// the next step's force point u_p at stage 2) decided on the last row in the scalar's order
// before the back substitutions that apply them; the start is KimExplicit::initialize's.
//
// Per unknown and step a lane costs (central difference, no damping, either mass; counted at
// the loops in core/batch/cdm_kernel.hpp): the forward pass 2·u_t − u_{t−Δt}, times 1/Δt² (2
// mul 1 sub), M's row (1 mul for the off-diagonal product shared by two rows, 1 FMA, 1 add), K's
// row (2 mul, 2 add, and the subtraction from M's), the forward sweep (1 mul 1 FMA); the back
// substitution 2 FMA: 6 mul + 4 FMA + 5 add/sub = 19 flops in 15 instructions (HHT's step: 23
// in 14), with 2 stores per unknown and register (HHT's: 4). While some lane is in contact the
// back substitution also subtracts λ·A⁻¹·e_c (1 mul 1 sub 1 blend). The velocity and the
// contact are computed at the contact node only. Noh–Bathe (core/batch/noh_bathe_kernel.hpp counts
// it): 43 flops in 37 instructions a step of two stages, 10 stores per unknown and register;
// Kim's (kim_step_lanes): 47 flops in 41 instructions a step of two stages, 9 stores.
//
// What batches (explicit_batch_kind, through batchable / same_batch): central difference with
// either velocity variant, Noh–Bathe and Kim's scheme with any p, on an undamped rod with a lumped
// or a consistent mass (damped runs go through simulate()), single wall, Lagrange contact, no
// histories; a batch holds one method, its lanes the same rod and time step, each its own gap,
// velocity, end time and the method's parameter (the velocity variant, p). KR-α has its own
// kernel (core/batch/batched_kr_alpha.hpp).
//
// Thread safety: one BatchWorkspace per thread; simulate_explicit_batch is reentrant.
#pragma once

#include <span>

#include "core/batch/batched_simulation.hpp"
#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"
#include "core/run/simulation.hpp"

namespace impactid {

/// The explicit methods with a batched step, each its own kind of batch.
enum class ExplicitBatchKind {
  none,                ///< not an explicit method of this kernel
  central_difference,  ///< cdm
  noh_bathe,           ///< noh-bathe
  kim_explicit,        ///< kim-explicit
};

/// Which explicit batch a method would join (none for every other method).
ExplicitBatchKind explicit_batch_kind(const MethodParams& method);

/// Whether the explicit kernel steps this run, given that the scene and options are otherwise
/// batchable (single wall, Lagrange, no histories: batchable() checks those): an explicit method
/// it knows, and for central difference an undamped rod.
bool explicit_batchable(const RodScene& scene, const MethodParams& method);

/// simulate_batch for runs of one ExplicitBatchKind (every pair batchable, every scene
/// same_batch with the first; all valid): summaries[k] and workspace.traces[k] are what
/// simulate() gives for scenes[k] with methods[k]. wall_time_s is the batch's time divided by the
/// number of runs in it.
void simulate_explicit_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchWorkspace& workspace, std::span<RunSummary> summaries);

}  // namespace impactid
