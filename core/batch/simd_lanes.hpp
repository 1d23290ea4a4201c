// The vocabulary of the batched kernels (core/batch/rod_kernel.cpp: the rod;
// core/batch/chain_kernel.cpp: any chain of bodies): kBatchLanes doubles as registers of the kernel
// level's width and the lane by lane IEEE operations on them, the rows of a tridiagonal product,
// and what a lane keeps of its run. Every helper is always_inline: it is compiled into the kernel
// that calls it, never called.
//
// Internal to core/: included by the kernels' files only, after core/batch/kernel_target.hpp, which
// sets the level (IMPACTID_KERNEL_LEVEL), its target and the register width. Everything here
// lives in the level's inline namespace, so that the 256-bit and the 512-bit definitions of the
// same names never meet at link time.
//
// Thread safety: values and pure functions.
#pragma once

#include <immintrin.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <utility>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/common/run_record.hpp"
#include "core/common/state.hpp"

#if !defined(IMPACTID_KERNEL_NAMESPACE)
#error "core/batch/simd_lanes.hpp: include core/batch/kernel_target.hpp first"
#endif

// Lanes travel by value only into helpers inlined into one function (always_inline), so GCC's
// note that returning wide vectors differs between targets does not concern these files.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace impactid::simd {
inline namespace IMPACTID_KERNEL_NAMESPACE {

// One register: kRegisterLanes doubles, the level's native vector (8 on x86-64-v4, 4 on
// x86-64-v3); may_alias: registers are read from LaneBlock storage. Why native: a GCC vector
// wider than the target's registers is lowered through the stack, lane by lane: the 512-bit
// registers of the first kernels cost a large stack frame, lane-by-lane moves and most of the
// speed on AVX2 (docs/performance.md).
constexpr int kRegisterLanes = IMPACTID_KERNEL_REGISTER_LANES;

// The runs a kernel steps together: 16 on x86-64-v4 (two registers), 8 on x86-64-v3 (two
// registers too). A batch of kBatchLanes runs is stepped as kBatchLanes / kLanes sub-batches
// (for_each_sub_batch). Why not 16 lanes in four 256-bit registers: AVX2 has 16 registers
// against AVX-512's 32, and with four registers a lane value the step kept half its
// instructions on the stack (docs/performance.md).
constexpr int kLanes = IMPACTID_KERNEL_BATCH_LANES;
constexpr int kRegisters = kLanes / kRegisterLanes;
static_assert(kLanes % kRegisterLanes == 0 && kBatchLanes % kLanes == 0);

// The gap of a lane that never touches a wall (the unused lanes', the free ones').
constexpr double kInf = std::numeric_limits<double>::infinity();

// A sub-batch's share of a batch's per-run arrays (its start states, its traces).
template <class T>
using LaneSpan = std::span<T, kLanes>;

// Calls run(first, count) for each sub-batch of kLanes runs out of `runs` (at most kBatchLanes),
// with `sub(array)`: the sub-batch's part of one of the batch's per-run arrays.
template <class Run>
inline void for_each_sub_batch(std::size_t runs, Run&& run) {
  for (std::size_t first = 0; first < runs; first += kLanes) {
    run(first, std::min<std::size_t>(kLanes, runs - first));
  }
}
template <class T>
inline LaneSpan<T> sub_batch_part(std::array<T, kBatchLanes>& all, std::size_t first) {
  return LaneSpan<T>(all.data() + first, kLanes);
}
using Register = double __attribute__((vector_size(sizeof(double) * kRegisterLanes), may_alias));
using MaskRegister = std::int64_t __attribute__((vector_size(sizeof(double) * kRegisterLanes)));

// Calls f(std::integral_constant<int, 0>{}, …, <kRegisters − 1>{}): each register by a
// constant index, so that GCC's scalar replacement keeps every register of a Lanes in a
// machine register (it does not take arrays indexed in loops).
template <class F>
[[gnu::always_inline]] inline void for_each_register(F&& f) {
  [&]<int... k>(std::integer_sequence<int, k...>) __attribute__((always_inline)) {
    (f(std::integral_constant<int, k>{}), ...);
  }
  (std::make_integer_sequence<int, kRegisters>{});
}

// kBatchLanes doubles as kRegisters independent registers. Why several registers rather than one
// vector of kBatchLanes: the serial recurrences of the tridiagonal sweeps bound a step by their
// latency (a multiply, a subtract and a multiply per unknown); independent registers per unknown
// are independent chains that the processor overlaps.
struct __attribute__((may_alias)) Lanes {
  Register r[kRegisters];

  double operator[](int l) const { return r[l / kRegisterLanes][l % kRegisterLanes]; }
  void set(int l, double x) { r[l / kRegisterLanes][l % kRegisterLanes] = x; }
};
struct LaneMask {
  MaskRegister r[kRegisters];

  bool operator[](int l) const { return r[l / kRegisterLanes][l % kRegisterLanes] != 0; }
  void set(int l, bool on) { r[l / kRegisterLanes][l % kRegisterLanes] = on ? -1 : 0; }
};

// Lane-by-lane arithmetic, register by register: the same IEEE operation on every lane.
template <class Op>
[[gnu::always_inline]] inline Lanes each(const Lanes& a, const Lanes& b, Op op) {
  Lanes out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = op(a.r[k], b.r[k]); });
  return out;
}
[[gnu::always_inline]] inline Lanes operator+(const Lanes& a, const Lanes& b) {
  return each(
      a, b, [](Register x, Register y) __attribute__((always_inline)) { return x + y; });
}
[[gnu::always_inline]] inline Lanes operator-(const Lanes& a, const Lanes& b) {
  return each(
      a, b, [](Register x, Register y) __attribute__((always_inline)) { return x - y; });
}
[[gnu::always_inline]] inline Lanes operator*(const Lanes& a, const Lanes& b) {
  return each(
      a, b, [](Register x, Register y) __attribute__((always_inline)) { return x * y; });
}
[[gnu::always_inline]] inline Lanes operator/(const Lanes& a, const Lanes& b) {
  return each(
      a, b, [](Register x, Register y) __attribute__((always_inline)) { return x / y; });
}
[[gnu::always_inline]] inline Lanes operator-(const Lanes& a) {
  Lanes out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = -a.r[k]; });
  return out;
}

// a·b + c rounded once, lane by lane: the scalar path's std::fma. GCC's vector extensions have
// no fused multiply-add: the level's instruction, one per register. (Per-lane __builtin_fma,
// which GCC had to gather back into registers, left it lane by lane on 256-bit targets.)
[[gnu::always_inline]] inline Register fma(const Register& a, const Register& b,
                                           const Register& c) {
#if IMPACTID_KERNEL_REGISTER_LANES == 8
  return (Register)_mm512_fmadd_pd((__m512d)a, (__m512d)b, (__m512d)c);
#elif IMPACTID_KERNEL_REGISTER_LANES == 4
  return (Register)_mm256_fmadd_pd((__m256d)a, (__m256d)b, (__m256d)c);
#else
#error "core/batch/simd_lanes.hpp: no fused multiply-add for this register width"
#endif
}
[[gnu::always_inline]] inline Lanes fma(const Lanes& a, const Lanes& b, const Lanes& c) {
  Lanes out;
  for_each_register([&](auto k)
                        __attribute__((always_inline)) { out.r[k] = fma(a.r[k], b.r[k], c.r[k]); });
  return out;
}

// *to = x register by register. An assignment of the whole struct made GCC 12 copy it through
// the stack in the step loop (a store, a load and a store again), which the stores, the scarcest
// resource of the step, paid for.
[[gnu::always_inline]] inline void store(Lanes* to, const Lanes& x) {
  for_each_register([&](auto k) __attribute__((always_inline)) { to->r[k] = x.r[k]; });
}

// x in every lane of a register: one broadcast (GCC 12 turns both the per-lane loop and the
// initialiser {x, x, …} into one masked broadcast per lane).
[[gnu::always_inline]] inline Register splat_register(double x) {
#if IMPACTID_KERNEL_REGISTER_LANES == 8
  return (Register)_mm512_set1_pd(x);
#else
  return (Register)_mm256_set1_pd(x);
#endif
}
[[gnu::always_inline]] inline Lanes splat(double x) {
  const Register all = splat_register(x);
  Lanes out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = all; });
  return out;
}
[[gnu::always_inline]] inline Lanes operator*(double a, const Lanes& b) {
  return splat(a) * b;
}

// a > b lane by lane (all ones where it holds).
[[gnu::always_inline]] inline LaneMask greater(const Lanes& a, const Lanes& b) {
  LaneMask out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = a.r[k] > b.r[k]; });
  return out;
}
// a != 0 lane by lane (a NaN is not zero, as in the scalar comparison).
[[gnu::always_inline]] inline LaneMask nonzero(const Lanes& a) {
  LaneMask out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = a.r[k] != 0.0; });
  return out;
}
[[gnu::always_inline]] inline LaneMask operator&(const LaneMask& a, const LaneMask& b) {
  LaneMask out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = a.r[k] & b.r[k]; });
  return out;
}
[[gnu::always_inline]] inline LaneMask operator|(const LaneMask& a, const LaneMask& b) {
  LaneMask out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = a.r[k] | b.r[k]; });
  return out;
}

[[gnu::always_inline]] inline bool any_lane(const LaneMask& mask) {
  MaskRegister any = mask.r[0];
  for_each_register([&](auto k) __attribute__((always_inline)) {
    if constexpr (k > 0) any |= mask.r[k];
  });
  bool out = false;
  for (int l = 0; l < kRegisterLanes; ++l) out |= any[l] != 0;
  return out;
}

// `mask ? a : b` lane by lane (a blend: no arithmetic on the lanes it does not pick).
[[gnu::always_inline]] inline Lanes select(const LaneMask& mask, const Lanes& a, const Lanes& b) {
  Lanes out;
  for_each_register([&](auto k)
                        __attribute__((always_inline)) { out.r[k] = mask.r[k] ? a.r[k] : b.r[k]; });
  return out;
}

// One row of ImplicitIntegrator::predict in every lane. The row holds what the previous step
// left: with kDeferred u*, v* and a, whose update u = u* + b1·Δt²·a, v = v* + g1·Δt·a is done
// here first (the same operations as ImplicitIntegrator::update; lanes of c.plain_state, which
// start now, hold u, v, a already), else u, v, a. Stores this step's predictors u*, v* over u and
// v and returns the α_f-weighted u and (kDamping) v. `c` is a kernel's coefficients: dt2_b0,
// dt_g0, b1_dt2, g1_dt, plain_state.
struct WeightedRow {
  Lanes u, v;
};
template <bool kDeferred, bool kStartingLanes, bool kDamping, class Coefficients>
[[gnu::always_inline]] inline WeightedRow predict_row(const Coefficients& c, const Lanes& dt,
                                                      const Lanes& minus_af, Lanes* u_row,
                                                      Lanes* v_row, const Lanes& a) {
  Lanes u = *u_row, v = *v_row;
  if constexpr (kDeferred) {
    const Lanes u_updated = fma(c.b1_dt2, a, u), v_updated = fma(c.g1_dt, a, v);
    u = kStartingLanes ? select(c.plain_state, u, u_updated) : u_updated;
    v = kStartingLanes ? select(c.plain_state, v, v_updated) : v_updated;
  }
  const Lanes du = fma(dt, v, c.dt2_b0 * a);
  const Lanes up = u + du;
  const Lanes vp = fma(c.dt_g0, a, v);
  store(u_row, up);
  store(v_row, vp);
  WeightedRow w;
  w.u = fma(minus_af, du, up);
  if constexpr (kDamping) w.v = fma(minus_af, c.dt_g0 * a, vp);
  return w;
}

// A tridiagonal matrix's three diagonals as plain pointers: held in registers across the step
// loop (the Lanes stores may alias anything, so members reached through a reference would be
// reloaded after every store).
struct Diagonals {
  const double *lower, *diag, *upper;
  explicit Diagonals(const Tridiagonal& m)
      : lower(m.lower.data()), diag(m.diag.data()), upper(m.upper.data()) {}
};

// Row i of a tridiagonal product with the neighbours `prev`, `cur`, `next` of x, summed in
// Tridiagonal::multiply_add's order: (l·x₋ + d·x) + u·x₊, the end rows without the missing term.
// (For C and M; K's rows are Tridiagonal::multiply's, fused: stiffness_row.)
template <bool kFirst, bool kLast>
[[gnu::always_inline]] inline Lanes row(const Diagonals& m, Eigen::Index i, const Lanes& prev,
                                        const Lanes& cur, const Lanes& next) {
  if constexpr (kFirst) return splat(m.diag[i]) * cur + splat(m.upper[i]) * next;
  if constexpr (kLast) return splat(m.lower[i]) * prev + splat(m.diag[i]) * cur;
  return (splat(m.lower[i]) * prev + splat(m.diag[i]) * cur) + splat(m.upper[i]) * next;
}

// Row i of a·x from x's neighbours, in Tridiagonal::quadratic_form's order: d·x, then + l·x₋,
// then + u·x₊ (the end rows without the missing term): the energy's rows.
[[gnu::always_inline]] inline Lanes quadratic_form_row(const Tridiagonal& a, Eigen::Index i,
                                                       const Lanes& prev, const Lanes& cur,
                                                       const Lanes& next) {
  Lanes r = splat(a.diag[i]) * cur;
  if (i > 0) r = r + splat(a.lower[i]) * prev;
  if (i + 1 < a.size()) r = r + splat(a.upper[i]) * next;
  return r;
}

// What run_steps in core/run/simulation.cpp keeps for one run, per lane.
struct LaneRun {
  RunSummary* summary = nullptr;
  ContactTrace* trace = nullptr;
  long first = 0;  // the first sample it computes (after its free flight)
  long last = -1;  // its last sample
  // The next sample at which it checks the energy: run_steps checks at every sample i with
  // (i − first + 1) a multiple of the interval, and at the last. A countdown rather than a
  // modulo: 2·kBatchLanes integer divisions per step cost measurably (docs/performance.md).
  long next_check = 0;
  bool stepping = false;
  double energy_bound = 0.0;
};

// Writes lane `lane` of the [unknown][lane] arrays u, v, a (n unknowns) from a state, or zeros
// it (state null): a lane that starts, or one that stops and then steps zeros at no risk.
inline void set_lane_state(Lanes* u, Lanes* v, Lanes* a, Eigen::Index n, int lane,
                           const State* state) {
  for (Eigen::Index i = 0; i < n; ++i) {
    u[i].set(lane, state ? state->u[i] : 0.0);
    v[i].set(lane, state ? state->v[i] : 0.0);
    a[i].set(lane, state ? state->a[i] : 0.0);
  }
}

// Writes the buffered samples [begin, through] of a scene with a list of m contacts into the
// traces of the lanes stepping now (which stepped at every one of them: a lane starts or stops
// only at an event, and events flush first). `chunk` holds, sample after sample, the m contacts'
// pressures and then their velocities; a lane's primary contact also fills its trace's main
// columns, as run_listed_steps (core/run/simulation.cpp) records them.
inline void flush_contact_chunk(std::array<LaneRun, kLanes>& lanes,
                                const std::array<int, kLanes>& primary, const Lanes* chunk, int m,
                                long begin, long through) {
  for (int l = 0; l < kLanes; ++l) {
    LaneRun& run = lanes[static_cast<std::size_t>(l)];
    if (!run.stepping || through < begin) continue;
    const auto main = static_cast<std::size_t>(primary[static_cast<std::size_t>(l)]);
    ContactTrace& trace = *run.trace;
    for (long i = begin; i <= through; ++i) {
      const Lanes* sample = chunk + 2 * m * (i - begin);
      for (int k = 0; k < m; ++k) {
        trace.contact_pressure[static_cast<std::size_t>(k)][i] = sample[k][l];
        trace.contact_velocity[static_cast<std::size_t>(k)][i] = sample[m + k][l];
      }
      trace.pressure[i] = trace.contact_pressure[main][i];
      trace.velocity[i] = trace.contact_velocity[main][i];
    }
    run.summary->steps = through + 1;
  }
}

inline void stop_unstable(LaneRun& run, std::string message) {
  run.summary->status = RunStatus::unstable;
  run.summary->message = std::move(message);
  run.stepping = false;
}

// The samples [first, last] that some lane of a batch computes (first > last: none).
inline std::pair<long, long> lane_samples(const std::array<LaneRun, kLanes>& lanes) {
  long begin = std::numeric_limits<long>::max(), end = -1;
  for (const LaneRun& run : lanes) {
    if (run.first > run.last) continue;
    begin = std::min(begin, run.first);
    end = std::max(end, run.last);
  }
  return {begin, end};
}

// The first sample at or after `i` at which some lane starts, checks its energy or ends
// (LONG_MAX: none).
inline long next_lane_event(const std::array<LaneRun, kLanes>& lanes, long i) {
  long next = std::numeric_limits<long>::max();
  for (const LaneRun& run : lanes) {
    if (run.stepping) {
      next = std::min({next, run.next_check, run.last});
    } else if (run.first >= i && run.first <= run.last) {
      next = std::min(next, run.first);
    }
  }
  return next;
}

// Whether some stepping lane checks its energy at sample i.
inline bool energy_due(const std::array<LaneRun, kLanes>& lanes, long i) {
  bool due = false;
  for (const LaneRun& run : lanes) due |= run.stepping && (i == run.last || i == run.next_check);
  return due;
}

// run_steps' energy check of a stepping lane at sample i, at time t (core/run/simulation.cpp): at
// its check samples and its last one, the energy becomes its final energy and a non-finite or
// grown one stops it as unstable.
inline void check_lane_energy(LaneRun& run, long i, double energy, double t, int interval,
                              double growth_limit) {
  RunSummary& summary = *run.summary;
  const bool check = i == run.last || i == run.next_check;
  if (i == run.next_check) run.next_check += interval;
  if (!check) return;
  summary.final_energy = energy;
  if (!std::isfinite(energy)) {
    stop_unstable(run, "non-finite values at t = " + format_value(t) + " s");
  } else if (summary.initial_energy > 0.0 && energy > run.energy_bound) {
    stop_unstable(run, "energy grew to " + format_value(energy / summary.initial_energy) +
                           " times the initial energy at t = " + format_value(t) + " s (bound " +
                           format_value(growth_limit) + ")");
  }
}

// Calls kernel.template operator()<kDamping, kMassTerm>() with the run's flags as constants: a
// kernel's four versions, each free of the branches of the terms it does not have. The kernel
// lambda must be always_inline too, so that it is compiled into the kernel that calls it.
template <class Kernel>
[[gnu::always_inline]] inline void with_kernel_flags(bool damping, bool mass_term,
                                                     Kernel&& kernel) {
  if (damping && mass_term) {
    kernel.template operator()<true, true>();
  } else if (damping) {
    kernel.template operator()<true, false>();
  } else if (mass_term) {
    kernel.template operator()<false, true>();
  } else {
    kernel.template operator()<false, false>();
  }
}

// Zero in every lane whose λ and contact velocity are finite; NaN as soon as one lane's is not
// (x − x is NaN for ±∞ and NaN). Lanes that are not stepping hold a zero state, so they pass.
[[gnu::always_inline]] inline bool all_finite(const Lanes& lambda, const Lanes& velocity) {
  Register probe{};
  for_each_register([&](auto k) __attribute__((always_inline)) {
    probe += (lambda.r[k] - lambda.r[k]) + (velocity.r[k] - velocity.r[k]);
  });
  double sum = 0.0;
  for (int l = 0; l < kRegisterLanes; ++l) sum += probe[l];
  return sum == 0.0;
}

}  // namespace IMPACTID_KERNEL_NAMESPACE
}  // namespace impactid::simd
