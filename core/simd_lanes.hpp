// The vocabulary of the batched kernels (core/batched_simulation.cpp: the rod; core/
// batched_chain.cpp: any chain of bodies): kBatchLanes doubles as two registers and the lane by
// lane IEEE operations on them, the rows of a tridiagonal product, and what a lane keeps of its
// run. Every helper is always_inline: it is compiled into each target version of the kernel that
// calls it (IMPACTID_SIMD_VERSIONS), never called.
//
// Internal to core/: the kernels' headers do not include it.
//
// Thread safety: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "core/batched_simulation.hpp"
#include "core/run_record.hpp"
#include "core/state.hpp"
#include "core/tridiagonal.hpp"

// Lanes travel by value only into helpers inlined into one function (always_inline), so GCC's
// note that returning wide vectors differs between targets does not concern these files.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace impactid::simd {

// One register of 8 doubles (GCC vector extensions: one AVX-512 register, two AVX2 ones);
// may_alias: registers are read from LaneBlock storage.
constexpr int kRegisterLanes = 8;
constexpr int kRegisters = kBatchLanes / kRegisterLanes;
static_assert(kBatchLanes % kRegisterLanes == 0);
using Register = double __attribute__((vector_size(sizeof(double) * kRegisterLanes), may_alias));
using MaskRegister = std::int64_t __attribute__((vector_size(sizeof(double) * kRegisterLanes)));

// kBatchLanes doubles as two independent registers. Why not one vector of kBatchLanes: the
// serial recurrences of the tridiagonal sweeps bound a step by their latency (a multiply, a
// subtract and a multiply per unknown); two registers per unknown are two independent chains
// that the processor overlaps, which nearly halves the time per lane. A single GCC vector of 16
// doubles is lowered through the stack instead, and so is an array of two registers (GCC's
// scalar replacement does not take arrays indexed in loops): named members stay in registers.
static_assert(kRegisters == 2, "Lanes holds two registers, lo and hi");
struct __attribute__((may_alias)) Lanes {
  Register lo, hi;

  double operator[](int l) const { return l < kRegisterLanes ? lo[l] : hi[l - kRegisterLanes]; }
  void set(int l, double x) {
    if (l < kRegisterLanes) {
      lo[l] = x;
    } else {
      hi[l - kRegisterLanes] = x;
    }
  }
};
struct LaneMask {
  MaskRegister lo, hi;

  bool operator[](int l) const {
    return (l < kRegisterLanes ? lo[l] : hi[l - kRegisterLanes]) != 0;
  }
  void set(int l, bool on) {
    if (l < kRegisterLanes) {
      lo[l] = on ? -1 : 0;
    } else {
      hi[l - kRegisterLanes] = on ? -1 : 0;
    }
  }
};

// Lane-by-lane arithmetic, register by register: the same IEEE operation on every lane.
[[gnu::always_inline]] inline Lanes operator+(const Lanes& a, const Lanes& b) {
  return {a.lo + b.lo, a.hi + b.hi};
}
[[gnu::always_inline]] inline Lanes operator-(const Lanes& a, const Lanes& b) {
  return {a.lo - b.lo, a.hi - b.hi};
}
[[gnu::always_inline]] inline Lanes operator*(const Lanes& a, const Lanes& b) {
  return {a.lo * b.lo, a.hi * b.hi};
}
[[gnu::always_inline]] inline Lanes operator/(const Lanes& a, const Lanes& b) {
  return {a.lo / b.lo, a.hi / b.hi};
}
[[gnu::always_inline]] inline Lanes operator-(const Lanes& a) {
  return {-a.lo, -a.hi};
}

// a·b + c rounded once, lane by lane: the scalar path's std::fma. GCC's vector extensions have
// no fused multiply-add, but in the x86-64-v3 and v4 versions of the kernels GCC turns these
// per-lane fused multiply-adds into one vfmadd per register; the baseline version calls the C
// library's fma per lane (correct, much slower: machines without FMA are from before 2013).
// Written lane by lane, not as a loop over the lanes: GCC 12 unrolls such a loop only after its
// loop vectoriser, and in Kim's kernel (core/batched_explicit.cpp), whose function is twice
// Noh–Bathe's, the basic-block vectoriser then left the forward sweep's fused multiply-adds
// scalar, eight vfnmadd…sd and the lane shuffles around them per register (docs/performance.md).
[[gnu::always_inline]] inline Register fma(const Register& a, const Register& b,
                                           const Register& c) {
  static_assert(kRegisterLanes == 8, "fma() names one lane of a register per term");
  return Register{__builtin_fma(a[0], b[0], c[0]), __builtin_fma(a[1], b[1], c[1]),
                  __builtin_fma(a[2], b[2], c[2]), __builtin_fma(a[3], b[3], c[3]),
                  __builtin_fma(a[4], b[4], c[4]), __builtin_fma(a[5], b[5], c[5]),
                  __builtin_fma(a[6], b[6], c[6]), __builtin_fma(a[7], b[7], c[7])};
}
[[gnu::always_inline]] inline Lanes fma(const Lanes& a, const Lanes& b, const Lanes& c) {
  return {fma(a.lo, b.lo, c.lo), fma(a.hi, b.hi, c.hi)};
}

// *to = x register by register. An assignment of the whole struct made GCC 12 copy it through
// the stack in the step loop (a store, a load and a store again), which the stores, the scarcest
// resource of the step, paid for.
[[gnu::always_inline]] inline void store(Lanes* to, const Lanes& x) {
  to->lo = x.lo;
  to->hi = x.hi;
}

// A shuffle of lane 0 into every lane of a register: GCC 12 turns both the per-lane loop
// `out[l] = x` and the initialiser {x, x, …} into one masked broadcast per lane, which made the
// step loop three times as long; this is one broadcast.
[[gnu::always_inline]] inline Lanes splat(double x) {
  const Register first{x};
  const Register all = __builtin_shufflevector(first, first, 0, 0, 0, 0, 0, 0, 0, 0);
  static_assert(kRegisterLanes == 8, "splat() names one index per lane of a register");
  return {all, all};
}
[[gnu::always_inline]] inline Lanes operator*(double a, const Lanes& b) {
  return splat(a) * b;
}

// a > b lane by lane. Written per lane: GCC 12 fails (internal compiler error in
// do_store_flag) on the vector comparison a > b when it lowers it for AVX2 or SSE2.
[[gnu::always_inline]] inline LaneMask greater(const Lanes& a, const Lanes& b) {
  LaneMask out;
  for (int l = 0; l < kBatchLanes; ++l) out.set(l, a[l] > b[l]);
  return out;
}

[[gnu::always_inline]] inline bool any_lane(const LaneMask& mask) {
  bool any = false;
  for (int l = 0; l < kRegisterLanes; ++l) any |= (mask.lo[l] | mask.hi[l]) != 0;
  return any;
}

// `mask ? a : b` lane by lane (a blend: no arithmetic on the lanes it does not pick).
[[gnu::always_inline]] inline Lanes select(const LaneMask& mask, const Lanes& a, const Lanes& b) {
  return {mask.lo ? a.lo : b.lo, mask.hi ? a.hi : b.hi};
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

// What run_steps in core/simulation.cpp keeps for one run, per lane.
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

inline void stop_unstable(LaneRun& run, std::string message) {
  run.summary->status = RunStatus::unstable;
  run.summary->message = std::move(message);
  run.stepping = false;
}

// The samples [first, last] that some lane of a batch computes (first > last: none).
inline std::pair<long, long> lane_samples(const std::array<LaneRun, kBatchLanes>& lanes) {
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
inline long next_lane_event(const std::array<LaneRun, kBatchLanes>& lanes, long i) {
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
inline bool energy_due(const std::array<LaneRun, kBatchLanes>& lanes, long i) {
  bool due = false;
  for (const LaneRun& run : lanes) due |= run.stepping && (i == run.last || i == run.next_check);
  return due;
}

// run_steps' energy check of a stepping lane at sample i, at time t (core/simulation.cpp): at
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
// lambda must be always_inline too, so that it is compiled into the calling target version.
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
  const Register probe = ((lambda.lo - lambda.lo) + (velocity.lo - velocity.lo)) +
                         ((lambda.hi - lambda.hi) + (velocity.hi - velocity.hi));
  double sum = 0.0;
  for (int l = 0; l < kRegisterLanes; ++l) sum += probe[l];
  return sum == 0.0;
}

}  // namespace impactid::simd
