#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/common/parameter_error.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/contact/stable_step_warning.hpp"
#include "core/methods/central_difference.hpp"
#include "core/methods/kim_explicit.hpp"
#include "core/methods/noh_bathe.hpp"
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

// `mask ? a : b` lane by lane as a blend of the bits (a mask lane is all ones or all zeros, as
// greater() sets it): the same bits as simd::select. In Kim's kernel GCC 12 lowered
// simd::select's vector conditional lane by lane, a compare and a branch per lane, where its
// masks are the second stage's contacts (docs/performance.md); the blend of the bits is one
// instruction per register (vpternlogq).
[[gnu::always_inline]] inline Register select_bits(const MaskRegister& mask, const Register& a,
                                                   const Register& b) {
  return (Register)((mask & (MaskRegister)a) | (~mask & (MaskRegister)b));
}
[[gnu::always_inline]] inline Lanes select_bits(const LaneMask& mask, const Lanes& a,
                                                const Lanes& b) {
  Lanes out;
  for_each_register([&](auto k) __attribute__((always_inline)) {
    out.r[k] = select_bits(mask.r[k], a.r[k], b.r[k]);
  });
  return out;
}

// One row's numbers of central difference's step, the same in every lane: M's and K's diagonal
// entries and the factorisation of M/Δt² (TridiagonalFactorization's 1/pivot, −lower/pivot,
// −upper/pivot and the product of two upper ratios, negated where the sweeps negate them).
struct RowFactors {
  Lanes mass_diag, stiffness_diag, inverse_pivot, minus_lower_ratio, minus_upper_ratio,
      upper_ratio2;
};

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

// The forward pass's walk down the rod, shared by the three kernels: row(i, f) for the rows
// 0 … n − 1 in order, with kFirst and kLast template flags, each row's factors `f` read from the
// rows' arrays (row_factors(b, i)) except on the uniform rows, whose factors `uniform` the caller
// holds in registers, two rows an iteration there.
template <class Rows, class Row>
[[gnu::always_inline]] inline void forward_rows(const Rows& b, const RowFactors& uniform,
                                                Row&& row) {
  const Eigen::Index last = b.n - 1;
  row.template operator()<true, false>(0, row_factors(b, 0));
  const Eigen::Index uniform_begin = std::max<Eigen::Index>(b.uniform_begin, 1);
  const Eigen::Index uniform_end = std::min(b.uniform_end, last);
  Eigen::Index i = 1;
  for (; i < std::min(uniform_begin, last); ++i) {
    row.template operator()<false, false>(i, row_factors(b, i));
  }
#pragma GCC unroll 2
  for (; i < uniform_end; ++i) row.template operator()<false, false>(i, uniform);
  for (; i < last; ++i) row.template operator()<false, false>(i, row_factors(b, i));
  row.template operator()<false, true>(last, row_factors(b, last));
}

// Row i of K·u (Tridiagonal::multiply: (l·u₋ + d·u) + u·u₊, the end rows without the missing
// term), from the off-diagonal products q = k·u of its neighbours, each shared by two rows.
template <bool kFirst, bool kLast>
[[gnu::always_inline]] inline Lanes stiffness_row(const Lanes& diag, const Lanes& prev_q,
                                                  const Lanes& u, const Lanes& next_q) {
  if constexpr (kFirst) {
    return diag * u + next_q;
  } else if constexpr (kLast) {
    return prev_q + diag * u;
  } else {
    return (prev_q + diag * u) + next_q;
  }
}

// Row i of the forward sweep (TridiagonalFactorization's): y_i·(1/pivot_i) −
// (l_i/pivot_i)·y_{i−1}, one FMA, stored at *out; `eliminated` carries y_{i−1} to the next row.
template <bool kFirst>
[[gnu::always_inline]] inline void sweep_row(const RowFactors& f, const Lanes& rhs,
                                             Lanes& eliminated, Lanes* out) {
  Lanes r = rhs * f.inverse_pivot;
  if constexpr (!kFirst) r = fma(f.minus_lower_ratio, eliminated, r);
  store(out, r);
  eliminated = r;
}

// The back substitution (TridiagonalFactorization::backward_in_place) of the forward sweep's y in
// y_rows, shared by the three kernels: x_{n−2} = y_{n−2} − c'·x_{n−1}, then
// x_i = (y_i − c'_i·y_{i+1}) + c'_i·c'_{i+1}·x_{i+2}, calling finish(i, x_i) with each solved x_i,
// the last row's first, then up the rod. The solved values carry the recurrence; finish stores
// what the row's step makes of them (it may overwrite y_i: each y is read before its finish).
template <class Rows, class Finish>
[[gnu::always_inline]] inline void back_substitute(const Rows& b, const RowFactors& uniform,
                                                   const Lanes* y_rows, Finish&& finish) {
  const Eigen::Index last = b.n - 1;
  Lanes x1 = y_rows[last];  // x_{i+1}
  finish(last, x1);
  Lanes x2{};    // x_{i+2}
  Lanes y_next;  // y_{i+1}
  {
    const Eigen::Index i = last - 1;
    y_next = y_rows[i];
    x2 = x1;
    x1 = fma(-splat(b.upper_ratio[i]), x1, y_next);
    finish(i, x1);
  }
  const auto backward = [&](Eigen::Index i, const Lanes& minus_ratio, const Lanes& ratio2)
      __attribute__((always_inline)) {
    const Lanes y = y_rows[i];
    const Lanes solved = fma(ratio2, x2, fma(minus_ratio, y_next, y));
    finish(i, solved);
    y_next = y;
    x2 = x1;
    x1 = solved;
  };
  const Eigen::Index uniform_last = b.uniform_end - 1;  // rows above it are generic
  Eigen::Index i = last - 2;
  for (; i > uniform_last; --i) {
    const RowFactors f = row_factors(b, i);
    backward(i, f.minus_upper_ratio, f.upper_ratio2);
  }
#pragma GCC unroll 2
  for (; i >= b.uniform_begin; --i) backward(i, uniform.minus_upper_ratio, uniform.upper_ratio2);
  for (; i >= 0; --i) {
    const RowFactors f = row_factors(b, i);
    backward(i, f.minus_upper_ratio, f.upper_ratio2);
  }
}

// The rows [begin, end) of one value, which the kernels hold in registers: ending before the last
// two (whose upper_ratio2 is 0 and whose diagonal is the end's), beginning where every array of
// `per_row` has reached the value of the row before them (a lumped mass: row 1; a consistent one:
// where its pivots have converged). Bit for bit: the kernels' rows are checked, not assumed.
struct UniformRows {
  Eigen::Index begin, end;
};
UniformRows uniform_rows(Eigen::Index n, std::initializer_list<const double*> per_row) {
  UniformRows rows;
  rows.end = std::max<Eigen::Index>(n - 2, 1);
  const Eigen::Index ref = rows.end - 1;
  const auto same_row = [&](Eigen::Index i) {
    return std::all_of(per_row.begin(), per_row.end(),
                       [&](const double* values) { return values[i] == values[ref]; });
  };
  rows.begin = ref >= 1 ? ref : rows.end;
  while (rows.begin > 1 && same_row(rows.begin - 1)) --rows.begin;
  return rows;
}

// upper_ratio_i·upper_ratio_{i+1}, as TridiagonalFactorization::factor forms it (0 on the last
// two rows).
Eigen::VectorXd upper_ratio_products(const Eigen::VectorXd& upper_ratio) {
  const Eigen::Index n = upper_ratio.size();
  Eigen::VectorXd products(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    products[i] = i + 2 < n ? upper_ratio[i] * upper_ratio[i + 1] : 0.0;
  }
  return products;
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
  // (core/batch/rod_kernel.cpp's step_lanes).
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
  const LaneMask closes = greater(free_end, b.gap);
  Lanes lambda{};
  // The back substitution in place; where some lane's contact closes, those lanes corrected by
  // −λ·A⁻¹·e_c as the scalar step corrects its solution.
  if (any_lane(closes)) {
    lambda = select(closes, (free_end - b.gap) / splat(b.influence[last]), Lanes{});
    back_substitute(
        b, uniform, y, [&](Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
          store(&y[i], select(closes, x - lambda * splat(b.influence[i]), x));
        });
    // u₊ − λ·A⁻¹·e_c at the node, then exactly the wall (CentralDifference::step).
    store(&y[last], select(closes, b.gap, free_end));
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

// Whether a tridiagonal matrix's off-diagonals are one value, lower = upper (the rod's).
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
    const auto& method = std::get<CentralDifferenceParams>(methods[lane]);
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

// ---- The explicit stage schemes: Noh–Bathe's (core/methods/noh_bathe.hpp) and Kim's
// (core/methods/kim_explicit.hpp) ----

// What both schemes' solves read, M·a = −K·u twice a step: K's rows, M's factorisation (the
// RowFactors' names), M⁻¹·e_c, and the uniform rows (as CdmRows').
struct StageSolveRows {
  Eigen::Index n;
  const double *stiffness_diag, *inverse_pivot, *lower_ratio, *upper_ratio, *upper_ratio2,
      *influence;
  double stiffness_off;
  Eigen::Index uniform_begin, uniform_end;
};

[[gnu::always_inline]] inline RowFactors row_factors(const StageSolveRows& b, Eigen::Index i) {
  return {Lanes{},
          splat(b.stiffness_diag[i]),
          splat(b.inverse_pivot[i]),
          -splat(b.lower_ratio[i]),
          -splat(b.upper_ratio[i]),
          splat(b.upper_ratio2[i])};
}

// The forward pass of a stage's solve_acceleration from the displacement `u`: 0 − K·u
// (Tridiagonal::multiply_add with −1 onto a zeroed a), then the forward sweep with M's
// factorisation into `out`. before_row(i, u_i) runs on each row first, after the next row's u is
// read (Noh–Bathe's second sub-step moves the row's state on there).
template <class BeforeRow>
[[gnu::always_inline]] inline void stage_forward(const StageSolveRows& b, const RowFactors& uniform,
                                                 const Lanes* u, Lanes* out,
                                                 BeforeRow&& before_row) {
  const Lanes zero{}, stiffness_off = splat(b.stiffness_off);
  struct Ahead {
    Lanes u, q;
  };
  const auto load = [&](Eigen::Index j) __attribute__((always_inline)) {
    Ahead x;
    x.u = u[j];
    x.q = stiffness_off * x.u;
    return x;
  };
  Ahead prev{}, cur = load(0), next{};
  Lanes eliminated{};
  forward_rows(
      b, uniform,
      [&]<bool kFirst, bool kLast>(Eigen::Index i, const RowFactors& f)
          __attribute__((always_inline)) {
            if constexpr (!kLast) next = load(i + 1);
            before_row(i, cur.u);
            const Lanes stiffness =
                stiffness_row<kFirst, kLast>(f.stiffness_diag, prev.q, cur.u, next.q);
            sweep_row<kFirst>(f, zero - stiffness, eliminated, &out[i]);
            prev = cur;
            cur = next;
          });
}
[[gnu::always_inline]] inline void stage_forward(const StageSolveRows& b, const RowFactors& uniform,
                                                 const Lanes* u, Lanes* out) {
  stage_forward(b, uniform, u, out,
                [](Eigen::Index, const Lanes&) __attribute__((always_inline)){});
}

// ½vᵀMv + ½uᵀKu of every lane (SecondOrderSystem::energy), each form in
// Tridiagonal::quadratic_form's order.
[[gnu::always_inline]] inline Lanes plain_energy_lanes(const Tridiagonal& mass,
                                                       const Tridiagonal& stiffness, const Lanes* u,
                                                       const Lanes* v, Eigen::Index n) {
  Lanes kinetic{}, strain{};
  for (Eigen::Index i = 0; i < n; ++i) {
    const Lanes v_prev = i > 0 ? v[i - 1] : Lanes{}, v_next = i + 1 < n ? v[i + 1] : Lanes{};
    const Lanes u_prev = i > 0 ? u[i - 1] : Lanes{}, u_next = i + 1 < n ? u[i + 1] : Lanes{};
    kinetic = kinetic + v[i] * quadratic_form_row(mass, i, v_prev, v[i], v_next);
    strain = strain + u[i] * quadratic_form_row(stiffness, i, u_prev, u[i], u_next);
  }
  return 0.5 * kinetic + 0.5 * strain;
}

// A batch of an explicit stage scheme: its rows (Rows: the solve's, the lanes' arrays u, v, a,
// next, sub_a and the scheme's own, the gap and the scheme's coefficients), the energy's
// matrices, the bookkeeping of core/batch/batch_lanes.hpp.
template <class Rows>
struct StageBatch {
  Rows rows;
  const Tridiagonal *mass, *stiffness;
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;  // each lane's state after initialize
  Lanes* start_next;       // and its first force point u_p, [unknown][lane]
  LaneLoop loop;
};

// The batch loop (core/batch/batch_lanes.hpp: run_lanes) of an explicit stage scheme with its step
// Scheme::step_lanes, the body of each scheme's target-cloned function.
template <class Scheme>
[[gnu::always_inline]] inline void run_stage_lanes(StageBatch<typename Scheme::Rows>& b) {
  typename Scheme::Rows& rows = b.rows;
  const RowFactors uniform = row_factors(rows.solve, rows.solve.uniform_begin);
  const Eigen::Index n = rows.solve.n;
  // Lane l's start (its state, its u_p; the stages' arrays zeroed), or zeros (null).
  const auto set_lane = [&](int l, const State* start) __attribute__((always_inline)) {
    set_lane_state(rows.u, rows.v, rows.a, n, l, start);
    for (Eigen::Index i = 0; i < n; ++i) {
      rows.next[i].set(l, start ? b.start_next[i][l] : 0.0);
      for (Lanes* stage : Scheme::stage_arrays(rows)) stage[i].set(l, 0.0);
    }
  };
  run_lanes(b.lanes, b.loop,
            lane_stepper(
                [&](int l) __attribute__((always_inline)) {
                  const State& start = b.start[static_cast<std::size_t>(l)];
                  set_lane(l, &start);
                  return LaneStart{.lambda = start.lambda, .t = start.t};
                },
                [&](bool, const Lanes&)
                    __attribute__((always_inline)) { return Scheme::step_lanes(rows, uniform); },
                [&]() __attribute__((always_inline)) { return rows.v[n - 1]; },
                [&]() __attribute__((always_inline)) {
                  return plain_energy_lanes(*b.mass, *b.stiffness, rows.u, rows.v, n);
                },
                [&](int l) __attribute__((always_inline)) { set_lane(l, nullptr); }));
}

// simulate_explicit_batch for an explicit stage scheme (Scheme: NohBatheLanes, KimLanes), with
// the workspace's storage, start states and traces. M's factorisation and M⁻¹·e_c
// (ExplicitStageContact::initialize's) are every lane's: one rod. Each lane is started as
// simulate() starts it (run_noh_bathe, run_kim_explicit in core/run/simulation.cpp): the scheme's
// initialize with the lane's p and gap, the stable step and its warning.
template <class Scheme>
void simulate_stage_batch(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                          const RunOptions& options, std::vector<LaneBlock>& storage,
                          LaneSpan<State> starts, LaneSpan<ContactTrace> traces,
                          std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  SecondOrderSystem system = assemble_rod(scenes[0]);  // every lane's, its gap set per lane
  const Eigen::Index n = system.size();
  StageBatch<typename Scheme::Rows> b{};
  b.loop = loop_settings(scenes[0], options);
  const double dt = b.loop.dt;

  LaneStorage arrays(storage, Scheme::kArrays + 1, n);
  auto& rows = b.rows;
  rows.solve.n = n;
  arrays.take({&rows.u, &rows.v, &rows.a, &rows.next, &rows.sub_a});
  rows.gap = splat(kInf);               // unused lanes never touch a wall
  Scheme::set_batch(rows, arrays, dt);  // its own arrays and the unused lanes' constants
  b.start_next = arrays.take();
  b.mass = &system.mass;
  b.stiffness = &system.stiffness;
  b.start = starts.data();

  TridiagonalFactorization factorization;
  const bool factored = factorization.factor(system.mass);
  const bool uniform =
      symmetric_uniform_off_diagonals(system.stiffness) && system.contact_dof == n - 1;
  const Eigen::VectorXd influence =
      factored ? factorization.inverse_column(system.contact_dof) : Eigen::VectorXd();
  // Every lane prepared first: initialize changes a lane's start state (the contact at the
  // start corrects a), which a later lane of the same velocity would otherwise copy
  // (prepare_lane).
  std::array<bool, kLanes> prepared{};
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    prepared[lane] =
        prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, b.lanes[lane]);
  }
  typename Scheme::Stepper stepper;
  bool any = false;
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    if (!prepared[lane]) continue;
    const RodScene& scene = scenes[lane];
    LaneRun& run = b.lanes[lane];
    RunSummary& summary = summaries[lane];
    State& state = starts[lane];
    const State before = state;
    system.gap = scene.gap;
    const auto& params = std::get<typename Scheme::Params>(methods[lane]);
    const auto c = Scheme::coefficients(params);
    if (!stepper.initialize(system, c, dt, state) || !uniform) {
      summary.status = RunStatus::failed;
      summary.message = uniform ? std::string(Scheme::kName) + ": singular mass matrix"
                                : "batched kernel: the stiffness is not uniform along the rod";
      run = LaneRun{};
      continue;
    }
    summary.stable_dt = stepper.stable_step();
    summary.warning =
        stable_step_warning(stepper, Scheme::kName, params.p, Scheme::critical_omega(params.p), dt,
                            ContactLaw::lagrange);
    // initialize's first force point u_p = u₀ + pΔt·v₀ + ½(pΔt)²·a₀, with the contact at the start
    // (its λ and the correction of a are already in `state`).
    const double p = c.p;
    const double scale_start = 0.5 * (p * dt) * (p * dt);
    Eigen::VectorXd next = before.u + (p * dt) * before.v + scale_start * before.a;
    const Eigen::Index contact = system.contact_dof;
    if (next[contact] > system.gap) {
      const double lambda = (next[contact] - system.gap) / (scale_start * influence[contact]);
      next -= (scale_start * lambda) * influence;
      next[contact] = system.gap;
    }
    for (Eigen::Index i = 0; i < n; ++i) b.start_next[i].set(l, next[i]);
    Scheme::set_lane(rows, l, c, dt, scene.gap);
    any = true;
  }
  if (any) {
    const Eigen::VectorXd upper_ratio2 = upper_ratio_products(factorization.upper_ratios());
    StageSolveRows& solve = rows.solve;
    solve.stiffness_diag = system.stiffness.diag.data();
    solve.inverse_pivot = factorization.inverse_pivots().data();
    solve.lower_ratio = factorization.lower_ratios().data();
    solve.upper_ratio = factorization.upper_ratios().data();
    solve.upper_ratio2 = upper_ratio2.data();
    solve.influence = influence.data();
    solve.stiffness_off = system.stiffness.lower[1];
    const UniformRows uniform_range =
        uniform_rows(n, {solve.stiffness_diag, solve.inverse_pivot, solve.lower_ratio,
                         solve.upper_ratio, solve.upper_ratio2});
    solve.uniform_begin = uniform_range.begin;
    solve.uniform_end = uniform_range.end;
    Scheme::run(b);
  }
  finish_lanes(count, start, traces, summaries);
}

// ---- The Noh–Bathe explicit scheme (core/methods/noh_bathe.hpp) ----

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

// ---- Kim's two-stage explicit scheme (core/methods/kim_explicit.hpp) ----

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

void simulate_explicit_lanes(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchStorage workspace, std::span<RunSummary> summaries) {
  const ExplicitBatchKind kind = explicit_batch_kind(methods[0]);
  assert(kind != ExplicitBatchKind::none && "simulate_explicit_batch: not an explicit batch");
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    const auto sub_scenes = scenes.subspan(first, count);
    const auto sub_methods = methods.subspan(first, count);
    const auto sub_summaries = summaries.subspan(first, count);
    const LaneSpan<State> starts = sub_batch_part(workspace.starts, first);
    const LaneSpan<ContactTrace> traces = sub_batch_part(workspace.traces, first);
    switch (kind) {
      case ExplicitBatchKind::central_difference:
        simulate_cdm_batch(sub_scenes, sub_methods, options, workspace.blocks, starts, traces,
                           sub_summaries);
        return;
      case ExplicitBatchKind::noh_bathe:
        simulate_stage_batch<NohBatheLanes>(sub_scenes, sub_methods, options, workspace.blocks,
                                            starts, traces, sub_summaries);
        return;
      case ExplicitBatchKind::kim_explicit:
        simulate_stage_batch<KimLanes>(sub_scenes, sub_methods, options, workspace.blocks, starts,
                                       traces, sub_summaries);
        return;
      case ExplicitBatchKind::none:
        return;
    }
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
