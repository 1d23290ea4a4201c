// Central difference's batched kernel (core/methods/central_difference.hpp; why and how:
// core/batch/batched_explicit.hpp): its step and energy lane by lane, its batch loop and set-up.
//
// Part of core/batch/explicit_kernel.cpp, which includes it after core/batch/kernel_target.hpp:
// the three explicit kernels are one translation unit, so that the compiler inlines their shared
// walk and loop into each kernel as it did when they were one file (the same machine code). It
// includes only core/batch/ headers: the kernel file includes every other header first, before the
// level's target, so that their functions keep the baseline target.
#pragma once

#include "core/batch/batch_lanes.hpp"
#include "core/batch/explicit_rows.hpp"
#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

// What central difference's step reads: the rod's rows (shared by every lane) and the lanes'
// arrays and constants. Small, so that the step takes a local copy of it (see cdm_step_lanes).
struct CdmRows {
  Eigen::Index n;
  // Per row (n entries each), as the scalar step reads them.
  const double *mass_diag, *stiffness_diag, *inverse_pivot, *lower_ratio, *upper_ratio,
      *upper_ratio2, *influence;
  // M's and K's off-diagonals: one value each, lower = upper (checked), so a row's product with
  // its lower neighbour is the one its neighbour's upper term needs.
  double mass_off, stiffness_off;
  // Rows [uniform_begin, uniform_end) have every RowFactors value of row uniform_begin, bit for
  // bit (checked): held in registers there.
  Eigen::Index uniform_begin, uniform_end;
  // Three arrays that rotate at every step: u_{t−Δt}, u_t, and the one the step writes u_{t+Δt}
  // into (holding u_{t−2Δt} before it).
  Lanes *previous, *current, *next;
  Lanes gap;
  // Paoli–Schatzman's e (ContactPenalties::restitution; 0 under Lagrange's law), the batch's: each
  // step's gap is then shifted by −e·(u₋ − gap), as CentralDifference::shifted_gap shifts it.
  double restitution;
  LaneMask backward_velocity;  // CdmVelocity::backward lanes; the others central
  double dt;
  double inv_dt2;  // 1/(Δt·Δt), as CentralDifference::step
  double two_dt;   // 2·Δt, the central velocity's divisor
};

// The batch: the step's rows, the energy's matrices and form, the bookkeeping of
// core/batch/batch_lanes.hpp.
struct CdmBatch {
  CdmRows rows;
  const Tridiagonal *mass, *stiffness;
  bool within_limit;  // CentralDifference::within_stability_limit: the energy's form
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;  // each lane's state at its start (its t)
  // Every lane's start as CentralDifference::initialize leaves it, u₋ (Taylor) and u, and the
  // array the first step (the state at the start, not a sample) writes u one step ahead into.
  Lanes *start_previous, *start_current, *start_next;
  LaneLoop loop;
};

[[gnu::always_inline]] inline RowFactors row_factors(const CdmRows& b, Eigen::Index i) {
  return {splat(b.mass_diag[i]),    splat(b.stiffness_diag[i]), splat(b.inverse_pivot[i]),
          -splat(b.lower_ratio[i]), -splat(b.upper_ratio[i]),   splat(b.upper_ratio2[i])};
}

// One step of central difference in every lane (CentralDifference::step, single wall, no
// damping): u_{t+Δt} into rows.next, returns λ_t; `velocity` gets the contact node's velocity at t
// (the lane's variant). The arrays are not rotated here.
//
// Flops per unknown and lane (count them below): the forward pass 2 mul 1 sub (the scaled
// increment s = (2·u − u₋)/Δt²), 1 mul 1 FMA 1 add (M·s: m·s_i shared by rows i − 1 and i + 1),
// 2 mul 2 add (K·u likewise) and 1 sub (M·s − K·u), 1 mul 1 FMA (the forward sweep); the back
// substitution 2 FMA, two rows at a time: 6 mul 4 FMA 5 add, 19 flops in 15 instructions.
// While some lane's contact closes the back substitution subtracts λ·A⁻¹·e_c too
// (1 mul 1 sub 1 blend), as the scalar step does after its solve.
[[gnu::always_inline]] inline Lanes cdm_step_lanes(const CdmRows& rows,
                                                   const RowFactors& uniform_row, Lanes& velocity) {
  // Local copies, so that the compiler keeps them in registers: a store through a Lanes pointer
  // (may_alias) could otherwise change them, and every use would reload them
  // (core/batch/rod_step.hpp's step_lanes).
  const CdmRows b = rows;
  const RowFactors uniform = uniform_row;
  const Eigen::Index last = b.n - 1;
  const Lanes* const u_previous = b.previous;
  const Lanes* const u = b.current;
  Lanes* const y = b.next;
  const Lanes two = splat(2.0), inv_dt2 = splat(b.inv_dt2);
  const Lanes mass_off = splat(b.mass_off), stiffness_off = splat(b.stiffness_off);

  // Row j's scaled increment s_j = (2·u_j − u₋_j)·(1/Δt²), u_j, and their products with the
  // off-diagonals (each shared by rows j − 1 and j + 1).
  struct Ahead {
    Lanes s, p, u, q;
  };
  const auto load = [&](Eigen::Index j) __attribute__((always_inline)) {
    Ahead a;
    a.u = u[j];
    a.s = (two * a.u - u_previous[j]) * inv_dt2;
    a.p = mass_off * a.s;
    a.q = stiffness_off * a.u;
    return a;
  };
  Ahead prev{}, cur = load(0), next{};
  Lanes eliminated{};
  // Row i of M·s (Tridiagonal::multiply: d·x fused onto the lower product, then + the upper),
  // minus row i of K·u (Tridiagonal::multiply_add with −1: (l·x₋ + d·x) + u·x₊), then the
  // forward sweep.
  forward_rows(
      b, uniform,
      [&]<bool kFirst, bool kLast>(Eigen::Index i, const RowFactors& f)
          __attribute__((always_inline)) {
            if constexpr (!kLast) next = load(i + 1);
            Lanes mass;
            if constexpr (kFirst) {
              mass = fma(f.mass_diag, cur.s, next.p);
            } else if constexpr (kLast) {
              mass = fma(f.mass_diag, cur.s, prev.p);
            } else {
              mass = fma(f.mass_diag, cur.s, prev.p) + next.p;
            }
            const Lanes stiffness =
                stiffness_row<kFirst, kLast>(f.stiffness_diag, prev.q, cur.u, next.q);
            // y + (−1)·(K·u)_i, exactly
            sweep_row<kFirst>(f, mass - stiffness, eliminated, &y[i]);
            prev = cur;
            cur = next;
          });

  // The contact (the rod's contact dof is the last): the forward sweep leaves the last unknown
  // final, so the test and λ = (u₊ − gap)/(A⁻¹·e_c)_c come before the back substitution.
  const Lanes free_end = y[last];
  const Lanes gap =
      b.restitution > 0.0 ? b.gap + splat(-b.restitution) * (u_previous[last] - b.gap) : b.gap;
  const LaneMask closes = greater(free_end, gap);
  Lanes lambda{};
  // The back substitution in place; where some lane's contact closes, those lanes corrected by
  // −λ·A⁻¹·e_c as the scalar step corrects its solution.
  if (any_lane(closes)) {
    lambda = select(closes, (free_end - gap) / splat(b.influence[last]), Lanes{});
    back_substitute(
        b, uniform, y, [&](Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
          store(&y[i], select(closes, x - lambda * splat(b.influence[i]), x));
        });
    // u₊ − λ·A⁻¹·e_c at the node, then exactly the wall (CentralDifference::step).
    store(&y[last], select(closes, gap, free_end));
  } else {
    back_substitute(
        b, uniform,
        y, [&](Eigen::Index i, const Lanes& x) __attribute__((always_inline)) { store(&y[i], x); });
  }
  // The reported velocity at t: central (u₊ − u₋)/(2Δt), backward (u − u₋)/Δt.
  const Lanes central = (y[last] - u_previous[last]) / splat(b.two_dt);
  const Lanes backward = (u[last] - u_previous[last]) / splat(b.dt);
  velocity = select(b.backward_velocity, backward, central);
  return lambda;
}

// The energy each lane's run_steps checks at the sample just stepped (CentralDifference::energy):
// after the rotation, b.previous holds u_t, b.current u_{t+Δt} and b.next u_{t−Δt}.
//   kWithinLimit: central_difference_energy(wᵀMw, wᵀKw, mᵀKm, Δt), w = (u₊ − u)/Δt,
//                 m = ½·(u₊ + u);
//   otherwise:    ½vᵀMv + ½uᵀKu with the lane's reported velocity v at t.
// Each quadratic form summed in Tridiagonal::quadratic_form's order ((d·x + l·x₋) + u·x₊ per
// row), the three sums side by side in one pass (forward_rows' walk).
template <bool kWithinLimit>
[[gnu::always_inline]] inline Lanes cdm_energy_lanes(const CdmRows& rows) {
  const CdmRows b = rows;  // a local copy: see cdm_step_lanes
  const Lanes dt = splat(b.dt), two_dt = splat(b.two_dt), half = splat(0.5);
  const Lanes mass_off = splat(b.mass_off), stiffness_off = splat(b.stiffness_off);
  const Lanes *u_previous = b.next, *u = b.previous, *u_ahead = b.current;
  // Row i's two vectors of the forms (w and m, or v and u).
  struct Row {
    Lanes first, second;
  };
  const auto vectors = [&](Eigen::Index i) __attribute__((always_inline)) {
    if constexpr (kWithinLimit) {
      return Row{(u_ahead[i] - u[i]) / dt, half * (u_ahead[i] + u[i])};
    } else {
      return Row{select(b.backward_velocity, (u[i] - u_previous[i]) / dt,
                        (u_ahead[i] - u_previous[i]) / two_dt),
                 u[i]};
    }
  };
  Lanes mass_first{}, stiffness_first{}, stiffness_second{};
  Row prev{}, cur = vectors(0), next{};
  const auto row = [&]<bool kFirst, bool kLast>(Eigen::Index i, const RowFactors& f)
      __attribute__((always_inline)) {
    if constexpr (!kLast) next = vectors(i + 1);
    Lanes m = f.mass_diag * cur.first, k = f.stiffness_diag * cur.first,
          k2 = f.stiffness_diag * cur.second;
    if constexpr (!kFirst) {
      m = m + mass_off * prev.first;
      k = k + stiffness_off * prev.first;
      k2 = k2 + stiffness_off * prev.second;
    }
    if constexpr (!kLast) {
      m = m + mass_off * next.first;
      k = k + stiffness_off * next.first;
      k2 = k2 + stiffness_off * next.second;
    }
    mass_first = mass_first + cur.first * m;
    stiffness_first = stiffness_first + cur.first * k;
    stiffness_second = stiffness_second + cur.second * k2;
    prev = cur;
    cur = next;
  };
  forward_rows(b, row_factors(b, b.uniform_begin), row);
  Lanes energy;
  for (int l = 0; l < kLanes; ++l) {
    energy.set(l, kWithinLimit ? central_difference_energy(mass_first[l], stiffness_first[l],
                                                           stiffness_second[l], b.dt)
                               : 0.5 * mass_first[l] + 0.5 * stiffness_second[l]);
  }
  return energy;
}

// Writes lane l of the three arrays from the [unknown][lane] arrays `now` (u_t) and `ahead`
// (u_{t+Δt}), or zeros it (null).
void set_cdm_lane(const CdmRows& b, int l, const Lanes* now, const Lanes* ahead) {
  for (Eigen::Index i = 0; i < b.n; ++i) {
    b.previous[i].set(l, now ? now[i][l] : 0.0);
    b.current[i].set(l, ahead ? ahead[i][l] : 0.0);
    b.next[i].set(l, 0.0);
  }
}

// The batch loop (core/batch/batch_lanes.hpp: run_lanes) with central difference's step: everything
// the loop calls is inlined.
void run_cdm_batch(CdmBatch& b) {
  CdmRows& rows = b.rows;
  const RowFactors uniform = row_factors(rows, rows.uniform_begin);
  Lanes velocity{};
  // simulate() steps once from the start before its loop: the state at the start (the initial
  // state or the last filled-in sample), not recorded, and u one step ahead. The same step for
  // every lane at once, each from its own start; a lane then steps on from u, u₊ when it starts.
  CdmRows start = rows;
  start.previous = b.start_previous;
  start.current = b.start_current;
  start.next = b.start_next;
  cdm_step_lanes(start, uniform, velocity);
  run_lanes(
      b.lanes, b.loop,
      lane_stepper(
          [&](int l) __attribute__((always_inline)) {
            set_cdm_lane(rows, l, b.start_current, b.start_next);
            // λ at the start does not enter central difference's step.
            return LaneStart{.lambda = 0.0, .t = b.start[static_cast<std::size_t>(l)].t};
          },
          [&](bool, const Lanes&) __attribute__((always_inline)) {
            const Lanes lambda = cdm_step_lanes(rows, uniform, velocity);
            Lanes* const oldest = rows.previous;
            rows.previous = rows.current;
            rows.current = rows.next;
            rows.next = oldest;
            return lambda;
          },
          [&]() __attribute__((always_inline)) { return velocity; },
          [&]() __attribute__((always_inline)) {
            return b.within_limit ? cdm_energy_lanes<true>(rows) : cdm_energy_lanes<false>(rows);
          },
          [&](int l) __attribute__((always_inline)) { set_cdm_lane(rows, l, nullptr, nullptr); }));
}
// Whether a tridiagonal matrix's off-diagonals are one value, lower = upper (the rod's); the stage
// schemes' set-up (core/batch/explicit_stage.hpp) asks it too.
bool symmetric_uniform_off_diagonals(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  for (Eigen::Index i = 1; i < n; ++i) {
    if (a.lower[i] != a.lower[1] || a.upper[i - 1] != a.lower[1]) return false;
  }
  return true;
}

// simulate_explicit_batch for central difference, with the workspace's storage, start states and
// traces.
void simulate_cdm_batch(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                        const RunOptions& options, std::vector<LaneBlock>& storage,
                        LaneSpan<State> starts, LaneSpan<ContactTrace> traces,
                        std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  const SecondOrderSystem system = assemble_rod(scenes[0]);  // every lane's, the gap aside
  const Eigen::Index n = system.size();
  CdmBatch b{};
  b.loop = loop_settings(scenes[0], options);
  const double dt = b.loop.dt;
  const ContactPenalties contact = resolve_contact(options.contact, system);

  LaneStorage arrays(storage, 6, n);
  CdmRows& rows = b.rows;
  rows.n = n;
  arrays.take({&rows.previous, &rows.current, &rows.next, &b.start_previous, &b.start_current,
               &b.start_next});
  rows.gap = splat(kInf);  // unused lanes never touch a wall
  rows.restitution = contact.restitution;
  rows.dt = dt;
  rows.inv_dt2 = 1.0 / (dt * dt);
  rows.two_dt = 2.0 * dt;
  b.mass = &system.mass;
  b.stiffness = &system.stiffness;
  b.start = starts.data();

  // The left-hand matrix M/Δt² (CentralDifference::initialize's, without damping:
  // explicit_batchable), so its factorisation and A⁻¹·e_c, are every lane's: one rod, one step.
  // So are the stable step and the energy's form, which a CentralDifference started once gives.
  const Tridiagonal lhs = system.mass.combined(1.0 / (dt * dt), system.damping, 0.0);
  TridiagonalFactorization factorization;
  CentralDifference stepper;
  State rest;  // any state of the rod's size: initialize's stable step does not depend on it
  rest.u.setZero(n);
  rest.v.setZero(n);
  rest.a.setZero(n);
  const bool started = factorization.factor(lhs) &&
                       stepper.initialize(system, CdmVelocity::central, dt, rest, contact);
  // The kernel's rows are checked, not assumed (never otherwise on a RodScene).
  const bool uniform = symmetric_uniform_off_diagonals(system.mass) &&
                       symmetric_uniform_off_diagonals(system.stiffness) &&
                       system.contact_dof == n - 1;
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    const RodScene& scene = scenes[lane];
    const auto method = std::get<CentralDifferenceCoefficients>(stepper_coefficients(methods[lane]));
    LaneRun& run = b.lanes[lane];
    if (!prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, run)) {
      continue;
    }
    RunSummary& summary = summaries[lane];
    if (!started || !uniform) {
      summary.status = RunStatus::failed;
      summary.message = !started ? "central difference: singular left-hand matrix"
                                 : "batched kernel: the mass or the stiffness is not uniform "
                                   "along the rod";
      run = LaneRun{};
      continue;
    }
    summary.stable_dt = stepper.stable_step();
    // CentralDifference::initialize's start: u₋ = u₀ − Δt·v₀ + ½Δt²·a₀, the same expression.
    const State& state = starts[lane];
    const Eigen::VectorXd u_previous = state.u - dt * state.v + (0.5 * dt * dt) * state.a;
    for (Eigen::Index i = 0; i < n; ++i) {
      b.start_previous[i].set(l, u_previous[i]);
      b.start_current[i].set(l, state.u[i]);
    }
    rows.gap.set(l, scene.gap);
    rows.backward_velocity.set(l, method.velocity == CdmVelocity::backward);
  }
  if (!started || !uniform) {
    finish_lanes(count, start, traces, summaries);
    return;
  }
  b.within_limit = stepper.within_stability_limit();
  const Eigen::VectorXd& inverse_pivot = factorization.inverse_pivots();
  const Eigen::VectorXd& lower_ratio = factorization.lower_ratios();
  const Eigen::VectorXd& upper_ratio = factorization.upper_ratios();
  const Eigen::VectorXd upper_ratio2 = upper_ratio_products(upper_ratio);
  const Eigen::VectorXd influence = factorization.inverse_column(system.contact_dof);
  rows.mass_diag = system.mass.diag.data();
  rows.stiffness_diag = system.stiffness.diag.data();
  rows.inverse_pivot = inverse_pivot.data();
  rows.lower_ratio = lower_ratio.data();
  rows.upper_ratio = upper_ratio.data();
  rows.upper_ratio2 = upper_ratio2.data();
  rows.influence = influence.data();
  rows.mass_off = system.mass.lower[1];  // n >= 2: a rod has at least one element
  rows.stiffness_off = system.stiffness.lower[1];
  const UniformRows uniform_range =
      uniform_rows(n, {rows.mass_diag, rows.stiffness_diag, rows.inverse_pivot, rows.lower_ratio,
                       rows.upper_ratio, rows.upper_ratio2});
  rows.uniform_begin = uniform_range.begin;
  rows.uniform_end = uniform_range.end;
  run_cdm_batch(b);
  finish_lanes(count, start, traces, summaries);
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
