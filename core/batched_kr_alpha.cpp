#include "core/batched_kr_alpha.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <variant>

#include "core/batch_lanes.hpp"
#include "core/function_versions.hpp"
#include "core/second_order_system.hpp"
#include "core/simd_lanes.hpp"
#include "core/tridiagonal.hpp"

namespace impactid {
namespace {

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

constexpr double kInf = std::numeric_limits<double>::infinity();

// One factorisation's numbers of a row in every lane: TridiagonalFactorization's 1/pivot,
// −lower/pivot, −upper/pivot (negated as the sweeps negate them) and the product of two upper
// ratios.
struct Factors {
  Lanes inverse_pivot, minus_lower_ratio, minus_upper_ratio, upper_ratio2;
};
// The same, [unknown][lane].
struct FactorRows {
  Lanes *inverse_pivot, *minus_lower_ratio, *minus_upper_ratio, *upper_ratio2;
};
// A row's factors of the three solves.
struct RowFactors {
  Factors mass, d, e;
};

// A tridiagonal matrix of the uniform rod in every lane: its first, interior and last diagonal
// entries and its off-diagonal (lower = upper, checked).
struct LaneDiagonals {
  Lanes first, interior, last, off;
};

// The step's constants of every lane, apart from KrRows: the step reads them through a pointer once
// a pass (each pass copies what it needs into registers), not in a copy of its own.
struct KrConstants {
  LaneDiagonals stiffness, mass_matrix, d_matrix;
  Lanes dt, minus_af, minus_rest, scale, lead, contact_denominator, gap;
};

// What KrAlphaExplicit::step reads, for every lane. Small (the arrays' pointers and the bounds;
// the constants apart, in KrConstants), so that the step takes a local copy of it (see
// kr_alpha_step_lanes).
struct KrRows {
  Eigen::Index n;
  FactorRows mass, d, e;
  // Rows [uniform_begin, uniform_end) have every factor of row uniform_begin in every lane, bit
  // for bit (checked): held in registers there. Within [1, n − 2).
  Eigen::Index uniform_begin, uniform_end;
  const KrConstants* constants;
  // The state: u (the sample's), u_next (u₂, fixed by the last equilibrium), v̂ already advanced by
  // Δt·w (the next step's first update, done at the end of this one), a; r and y scratch, w the
  // M·a and α1·a of the step (scratch too: see the header).
  Lanes *u, *u_next, *v_hat, *a, *r, *y, *w;
  // The step's response of a and of α1·a to a unit force on the contact dof (KrAlphaExplicit's
  // step_response_.a_main, .w_main).
  Lanes *a_response, *w_response;
  // M is diagonal (lumped): its factorisation's ratios are zeros and every 1/m_i > ½ (checked).
  // Then M's sweeps change nothing: with r_i·(1/m_i) finite and never −0 (r never is, and a product
  // with a factor above ½ does not underflow to zero), each fused multiply-add of the sweeps adds
  // ±0 to it and returns it. The step then does A, B and C in one pass (lumped_mass_pass). Also
  // checked, in every lane: D's diagonal, E's 1/pivots and its lower ratios (rows 1 on) are not
  // zero, so that a non-finite r_i·(1/m_i) makes row i of D·(M⁻¹·r − a) and of E's forward sweep
  // non-finite, and every row of the sweep after it: the sweep's last row is the step's probe.
  bool lumped_mass;
};

[[gnu::always_inline]] inline Factors factors(const FactorRows& f, Eigen::Index i) {
  return {f.inverse_pivot[i], f.minus_lower_ratio[i], f.minus_upper_ratio[i], f.upper_ratio2[i]};
}
[[gnu::always_inline]] inline RowFactors row_factors(const KrRows& b, Eigen::Index i) {
  return {factors(b.mass, i), factors(b.d, i), factors(b.e, i)};
}
// Row j's diagonal entry of a matrix of the rod.
[[gnu::always_inline]] inline Lanes diagonal(const LaneDiagonals& m, Eigen::Index j,
                                             Eigen::Index last) {
  return j == 0 ? m.first : j == last ? m.last : m.interior;
}

// Calls row.template operator()<kGeneric>(i, f) for every row, upwards (kUp) or downwards, with
// the row's factors of one solve: from its arrays outside [uniform_begin, uniform_end) (kGeneric:
// the row may be an end row or the one before the last), `uniform` inside it (an interior row).
// One factorisation at a time, a copy in registers: with all three the step's fused
// multiply-adds were split into per-lane scalar ones (GCC's vectoriser gave up on them).
template <bool kUp, class Row>
[[gnu::always_inline]] inline void each_row(const KrRows& b, const FactorRows& rows,
                                            const Factors& uniform_factors, Row&& row) {
  const Eigen::Index n = b.n;
  const Factors uniform = uniform_factors;
  if constexpr (kUp) {
    Eigen::Index i = 0;
    for (; i < b.uniform_begin; ++i) row.template operator()<true>(i, factors(rows, i));
#pragma GCC unroll 2
    for (; i < b.uniform_end; ++i) row.template operator()<false>(i, uniform);
    for (; i < n; ++i) row.template operator()<true>(i, factors(rows, i));
  } else {
    Eigen::Index i = n - 1;
    for (; i >= b.uniform_end; --i) row.template operator()<true>(i, factors(rows, i));
#pragma GCC unroll 2
    for (; i >= b.uniform_begin; --i) row.template operator()<false>(i, uniform);
    for (; i >= 0; --i) row.template operator()<true>(i, factors(rows, i));
  }
}

// A back substitution (TridiagonalFactorization::backward_in_place: x_{n−1} = y_{n−1},
// x_{n−2} = y_{n−2} − c'·x_{n−1}, then x_i = (y_i − c'_i·y_{i+1}) + c'_i·c'_{i+1}·x_{i+2}) that
// hands each row's solution to `visit` as soon as it is known, downwards:
// visit.template operator()<kGeneric>(i, x_i) (kGeneric as each_row's). 2 FMA.
template <class Visit>
[[gnu::always_inline]] inline void solve_down(const KrRows& b, const FactorRows& rows,
                                              const Factors& uniform, const Lanes* y_rows,
                                              Visit&& visit) {
  const Eigen::Index last = b.n - 1;
  Lanes x1{}, x2{}, y_next{};  // x_{i+1}, x_{i+2}, y_{i+1}
  each_row<false>(
      b, rows,
      uniform, [&]<bool kGeneric>(Eigen::Index i, const Factors& s) __attribute__((always_inline)) {
        const Lanes yi = y_rows[i];
        Lanes x;
        if (kGeneric && i == last) {
          x = yi;
        } else if (kGeneric && i == last - 1) {
          x = fma(s.minus_upper_ratio, x1, yi);
        } else {
          x = fma(s.upper_ratio2, x2, fma(s.minus_upper_ratio, y_next, yi));
        }
        y_next = yi;
        x2 = x1;
        x1 = x;
        visit.template operator()<kGeneric>(i, x);
      });
}

// solve_down fused with a product of the solution's rows as `combine` makes them
// (t_i = combine(i, x_i)) with a symmetric tridiagonal matrix: row j of it (Tridiagonal::multiply:
// d·t_j fused onto the lower neighbour's product, then + the upper's; each off-diagonal product
// shared by two rows) is written into `out` as soon as t_{j−1} is known. 2 FMA for the solve,
// 1 mul 1 FMA 1 add for the product.
template <class Combine>
[[gnu::always_inline]] inline void solve_down_multiply(const KrRows& b, const FactorRows& rows,
                                                       const Factors& uniform, const Lanes* y_rows,
                                                       const LaneDiagonals& diagonals, Lanes* out,
                                                       Combine&& combine) {
  const Eigen::Index last = b.n - 1;
  const LaneDiagonals matrix = diagonals;
  Lanes t1{}, t2{}, p1{}, p2{};  // t_{i+1}, t_{i+2} and their products with the off-diagonal
  solve_down(
      b, rows, uniform,
      y_rows, [&]<bool kGeneric>(Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
        const Lanes t = combine(i, x);
        const Lanes p = matrix.off * t;
        if (!(kGeneric && i == last)) {  // row j = i + 1
          const Eigen::Index j = i + 1;
          const Lanes d = kGeneric ? diagonal(matrix, j, last) : matrix.interior;
          Lanes row = fma(d, t1, p);
          if (!(kGeneric && j == last)) row = row + p2;
          store(&out[j], row);
        }
        t2 = t1;
        t1 = t;
        p2 = p1;
        p1 = p;
      });
  store(&out[0], b.n > 1 ? fma(matrix.first, t1, p2) : matrix.first * t1);
}

// A forward sweep (TridiagonalFactorization::forward_in_place: y_0·(1/pivot_0), then
// y_i·(1/pivot_i) − (l_i/pivot_i)·y_{i−1}, one FMA) of rows handed over upwards, one at a time,
// into `out`: 1 mul 1 FMA.
struct SweepUp {
  Lanes eliminated{};

  template <bool kGeneric>
  [[gnu::always_inline]] void row(Eigen::Index i, const Factors& s, const Lanes& value,
                                  Lanes* out) {
    Lanes y = value * s.inverse_pivot;
    if (!(kGeneric && i == 0)) y = fma(s.minus_lower_ratio, eliminated, y);
    store(&out[i], y);
    eliminated = y;
  }
};

// A forward sweep in place: 1 mul 1 FMA.
[[gnu::always_inline]] inline void sweep_up(const KrRows& b, const FactorRows& factor_rows,
                                            const Factors& uniform, Lanes* rows) {
  SweepUp sweep;
  each_row<true>(
      b, factor_rows,
      uniform, [&]<bool kGeneric>(Eigen::Index i, const Factors& s) __attribute__((always_inline)) {
        sweep.row<kGeneric>(i, s, rows[i], rows);
      });
}

// The forward sweep of (matrix·x) into `out`, the product's rows (Tridiagonal::multiply, as
// solve_down_multiply) formed as the sweep reaches them: 2 mul 2 FMA 1 add.
[[gnu::always_inline]] inline void multiply_sweep_up(const KrRows& b, const FactorRows& factor_rows,
                                                     const Factors& uniform, const Lanes* x_rows,
                                                     const LaneDiagonals& diagonals, Lanes* out) {
  const Eigen::Index last = b.n - 1;
  const LaneDiagonals matrix = diagonals;
  Lanes x = x_rows[0], p = matrix.off * x, p_prev{};  // x_i, its product with the off-diagonal
  SweepUp sweep;
  each_row<true>(
      b, factor_rows,
      uniform, [&]<bool kGeneric>(Eigen::Index i, const Factors& s) __attribute__((always_inline)) {
        Lanes x_next{}, p_next{};
        if (!(kGeneric && i == last)) {
          x_next = x_rows[i + 1];
          p_next = matrix.off * x_next;
        }
        const Lanes d = kGeneric ? diagonal(matrix, i, last) : matrix.interior;
        Lanes row;
        if (kGeneric && i == 0) {
          row = fma(d, x, p_next);
        } else if (kGeneric && i == last) {
          row = fma(d, x, p_prev);
        } else {
          row = fma(d, x, p_prev) + p_next;
        }
        sweep.row<kGeneric>(i, s, row, out);
        p_prev = p;
        x = x_next;
        p = p_next;
      });
}

// The rows of the right-hand side r = 0 + (−α_f)·K·u, then + (−(1 − α_f))·K·u₁
// (Tridiagonal::multiply_add's rows: (l·x₋ + d·x) + u·x₊, each off-diagonal product shared by two
// rows), asked for upwards, row 0 first: 6 mul 6 add. (K·u is the last step's K·u₁; keeping it in
// an array instead measured no faster.) Never −0: r starts as +0 + x.
class RightHandSide {
 public:
  [[gnu::always_inline]] explicit RightHandSide(const KrRows& b)
      : u_(b.u),
        u1_(b.u_next),
        last_(b.n - 1),
        off_(b.constants->stiffness.off),
        k_first_(b.constants->stiffness.first),
        k_interior_(b.constants->stiffness.interior),
        k_last_(b.constants->stiffness.last),
        minus_af_(b.constants->minus_af),
        minus_rest_(b.constants->minus_rest),
        cur_(load(0)) {}

  template <bool kGeneric>
  [[gnu::always_inline]] Lanes row(Eigen::Index i) {
    const bool first = kGeneric && i == 0, at_last = kGeneric && i == last_;
    if (!at_last) next_ = load(i + 1);
    const Lanes k = !kGeneric    ? k_interior_
                    : i == 0     ? k_first_
                    : i == last_ ? k_last_
                                 : k_interior_;
    Lanes now, ahead;
    if (first) {
      now = k * cur_.u + next_.q;
      ahead = k * cur_.u1 + next_.q1;
    } else if (at_last) {
      now = prev_.q + k * cur_.u;
      ahead = prev_.q1 + k * cur_.u1;
    } else {
      now = (prev_.q + k * cur_.u) + next_.q;
      ahead = (prev_.q1 + k * cur_.u1) + next_.q1;
    }
    Lanes r = Lanes{} + minus_af_ * now;  // r.setZero(), then +=: 0 + x is x but for −0
    r = r + minus_rest_ * ahead;
    prev_ = cur_;
    cur_ = next_;
    return r;
  }

 private:
  struct Ahead {
    Lanes u, q, u1, q1;
  };
  [[gnu::always_inline]] Ahead load(Eigen::Index j) const {
    Ahead x;
    x.u = u_[j];
    x.q = off_ * x.u;
    x.u1 = u1_[j];
    x.q1 = off_ * x.u1;
    return x;
  }

  const Lanes *u_, *u1_;
  Eigen::Index last_;
  Lanes off_, k_first_, k_interior_, k_last_, minus_af_, minus_rest_;
  Ahead prev_{}, cur_, next_{};
};

// A, B and C of the step in one pass upwards, for a lumped M (KrRows::lumped_mass): M⁻¹·r is
// r_i·(1/m_i), y = D·(M⁻¹·r − a) row by row as its upper neighbour is known, E's forward sweep on
// it. In a lane where some r_i·(1/m_i) is not finite, neither is the sweep's last row
// (KrRows::lumped_mass): the caller then does A, B and C instead. 9 mul 8 add/sub 2 FMA.
[[gnu::always_inline]] inline void lumped_mass_pass(const KrRows& b, const RowFactors& uniform) {
  const Eigen::Index n = b.n, last = n - 1;
  RightHandSide rhs(b);
  const LaneDiagonals dm = b.constants->d_matrix;
  const Lanes inverse_mass = uniform.mass.inverse_pivot;
  const Factors e = uniform.e;
  SweepUp sweep;
  Lanes t1{}, p1{}, p2{};  // t_{i−1}, p_{i−1}, p_{i−2}: p = D's off-diagonal · t
  const auto row = [&]<bool kGeneric>(Eigen::Index i) __attribute__((always_inline)) {
    const Lanes q =
        rhs.template row<kGeneric>(i) * (kGeneric ? b.mass.inverse_pivot[i] : inverse_mass);
    const Lanes t = q - b.a[i];
    const Lanes p = dm.off * t;
    if (!(kGeneric && i == 0)) {  // row j = i − 1 of D·t, then of E's sweep
      const Eigen::Index j = i - 1;
      if (kGeneric && j == 0) {
        sweep.row<true>(0, factors(b.e, 0), fma(dm.first, t1, p), b.y);
      } else if (kGeneric) {
        sweep.row<true>(j, factors(b.e, j), fma(diagonal(dm, j, last), t1, p2) + p, b.y);
      } else {
        sweep.row<false>(j, e, fma(dm.interior, t1, p2) + p, b.y);
      }
    }
    t1 = t;
    p2 = p1;
    p1 = p;
  };
  // Generic rows where row i or i − 1 is outside [uniform_begin, uniform_end).
  Eigen::Index i = 0;
  const Eigen::Index split = std::min(b.uniform_begin + 1, b.uniform_end);
  for (; i < split; ++i) row.template operator()<true>(i);
#pragma GCC unroll 2
  for (; i < b.uniform_end; ++i) row.template operator()<false>(i);
  for (; i < n; ++i) row.template operator()<true>(i);
  sweep.row<true>(last, factors(b.e, last), fma(dm.last, t1, p2), b.y);
}

// One step of KR-α in every lane (KrAlphaExplicit::step, single wall, no damping): the passes of
// the header. Returns λ of the equilibrium at t + Δt; `velocity` gets the contact dof's reported
// velocity v̂ + γΔt·w. Leaves u₁ in rows.u_next and u₂ in rows.u: the caller swaps them.
[[gnu::always_inline]] inline Lanes kr_alpha_step_lanes(const KrRows& rows,
                                                        const RowFactors& uniform_row,
                                                        Lanes& velocity) {
  // A local copy of the pointers and bounds, so that the compiler keeps them in registers: a store
  // through a Lanes pointer (may_alias) could otherwise change them, and every use would reload
  // them (core/batched_simulation.cpp's step_lanes). The constants (KrConstants) and `uniform` are
  // copied by each pass, as far as it uses them, into registers: a copy here too moved 2.7 KB a
  // step.
  const KrRows b = rows;
  const KrConstants& k = *b.constants;
  const RowFactors& uniform = uniform_row;
  const Eigen::Index last = b.n - 1;

  // ABC (lumped M): A, B and C in one pass, unless some r_i/m_i is not finite.
  bool fused = false;
  if (b.lumped_mass) {
    lumped_mass_pass(b, uniform);
    fused = all_finite(b.y[last], Lanes{});
  }
  if (!fused) {
    // A: r, M's forward sweep: 7 mul 6 add 1 FMA.
    RightHandSide rhs(b);
    SweepUp sweep;
    each_row<true>(
        b, b.mass, uniform.mass,
        [&]<bool kGeneric>(Eigen::Index i, const Factors& f) __attribute__((always_inline)) {
          sweep.row<kGeneric>(i, f, rhs.template row<kGeneric>(i), b.r);
        });
    // B: M's back substitution, r − a, D·(r − a) into y: 1 mul 2 add/sub 3 FMA.
    solve_down_multiply(
        b, b.mass, uniform.mass, b.r, k.d_matrix,
        b.y, [&](Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
          return x - b.a[i];
        });
    // C: E's forward sweep: 1 mul 1 FMA.
    sweep_up(b, b.e, uniform.e, b.y);
  }
  // D: E's back substitution, a += x: 2 FMA 1 add.
  solve_down(
      b, b.e, uniform.e,
      b.y, [&]<bool>(Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
        store(&b.a[i], b.a[i] + x);
      });
  // E: w = M·a and D's forward sweep on it: 2 mul 2 FMA 1 add.
  multiply_sweep_up(b, b.d, uniform.d, b.a, k.mass_matrix, b.w);

  // The contact (the rod's contact dof is the last, which the forward sweep leaves final): the
  // contact-free u₂ there and λ, by KrAlphaExplicit::enforce's expressions.
  const Lanes* const u1 = b.u_next;
  Lanes* const u2 = b.u;  // u, no longer needed: u₂ is written over it
  const Lanes dt = k.dt, scale = k.scale, gap = k.gap, lead = k.lead;
  const Lanes free_end = (u1[last] + dt * b.v_hat[last]) + scale * b.w[last];
  const LaneMask closes = greater(free_end, gap);
  const bool any = any_lane(closes);
  Lanes lambda{}, scaled{};
  if (any) {
    lambda = select(closes, (free_end - gap) / k.contact_denominator, Lanes{});
    scaled = scale * lambda;
  }
  // F: D's back substitution (w = α1·a), u₂ = (u₁ + Δt·v̂) + s·w, the contact's corrections,
  // v̂ += Δt·w: 3 mul 3 add 2 FMA.
  const auto solve = [&]<bool kContact>() __attribute__((always_inline)) {
    solve_down(
        b, b.d, uniform.d,
        b.w, [&]<bool kGeneric>(Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
          const Lanes v_hat = b.v_hat[i];
          Lanes next = (u1[i] + dt * v_hat) + scale * x;
          Lanes w = x;
          if constexpr (kContact) {
            const Lanes response = b.w_response[i];
            w = select(closes, x - lambda * response, x);
            next = select(closes, next - scaled * response, next);
            const Lanes a = b.a[i];
            store(&b.a[i], select(closes, a - lambda * b.a_response[i], a));
          }
          if (kGeneric && i == last) {
            next = select(closes, gap, next);  // exactly the wall, not a few ulps off
            velocity = v_hat + lead * w;
          }
          store(&u2[i], next);
          store(&b.v_hat[i], v_hat + dt * w);
        });
  };
  if (any) {
    solve.template operator()<true>();
  } else {
    solve.template operator()<false>();
  }
  return lambda;
}

// KrAlphaExplicit::energy of every lane after a step (u the sample's, u_next the next
// displacement): ½·wᵀM·w + ½·mᵀK·m, w = (u_next − u)/Δt, m = ½·(u + u_next), each form in
// Tridiagonal::quadratic_form's order.
[[gnu::always_inline]] inline Lanes kr_alpha_energy_lanes(const Tridiagonal& mass,
                                                          const Tridiagonal& stiffness,
                                                          const KrRows& b) {
  const Eigen::Index n = b.n;
  const Lanes half = splat(0.5), dt = b.constants->dt;
  const auto rate = [&](Eigen::Index i) __attribute__((always_inline)) {
    return (b.u_next[i] - b.u[i]) / dt;
  };
  const auto mean = [&](Eigen::Index i) __attribute__((always_inline)) {
    return half * (b.u[i] + b.u_next[i]);
  };
  // Each row's w and m formed once and slid along (a division per row, not three).
  Lanes kinetic{}, strain{};
  Lanes w_prev{}, w = rate(0), m_prev{}, m = mean(0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Lanes w_next = i + 1 < n ? rate(i + 1) : Lanes{};
    const Lanes m_next = i + 1 < n ? mean(i + 1) : Lanes{};
    kinetic = kinetic + w * quadratic_form_row(mass, i, w_prev, w, w_next);
    strain = strain + m * quadratic_form_row(stiffness, i, m_prev, m, m_next);
    w_prev = w;
    w = w_next;
    m_prev = m;
    m = m_next;
  }
  return half * kinetic + half * strain;
}

// Each lane's start as KrAlphaExplicit::initialize leaves it: u₂ and v̂ (already advanced by Δt·w,
// see KrRows); u, a and λ are in the lane's State.
struct KrStart {
  Eigen::VectorXd u_next, v_hat;
};

struct KrBatch {
  KrRows rows;
  KrConstants constants;
  const Tridiagonal *mass, *stiffness;
  std::array<LaneRun, kBatchLanes> lanes;
  std::array<State, kBatchLanes>* start;
  std::array<KrStart, kBatchLanes> kr_start;
  LaneLoop loop;
};

// The batch loop (core/batch_lanes.hpp: run_lanes) with KR-α's step, for the machine at hand (GCC
// target_clones: everything the loop calls is inlined into each version; its own function, as
// each kernel kind has: core/function_versions.hpp).
IMPACTID_SIMD_VERSIONS void run_kr_alpha_batch(KrBatch& b) {
  KrRows& rows = b.rows;
  const RowFactors uniform = row_factors(rows, rows.uniform_begin);
  const Eigen::Index n = rows.n;
  Lanes velocity{};
  const auto set_lane = [&](int l, const State* start, const KrStart* kr)
      __attribute__((always_inline)) {
    for (Eigen::Index i = 0; i < n; ++i) {
      rows.u[i].set(l, start ? start->u[i] : 0.0);
      rows.a[i].set(l, start ? start->a[i] : 0.0);
      rows.u_next[i].set(l, kr ? kr->u_next[i] : 0.0);
      rows.v_hat[i].set(l, kr ? kr->v_hat[i] : 0.0);
    }
  };
  run_lanes(b.lanes, b.loop,
            lane_stepper(
                [&](int l) __attribute__((always_inline)) {
                  const auto lane = static_cast<std::size_t>(l);
                  const State& start = (*b.start)[lane];
                  set_lane(l, &start, &b.kr_start[lane]);
                  return LaneStart{.lambda = start.lambda, .t = start.t};
                },
                [&](bool, const Lanes&) __attribute__((always_inline)) {
                  const Lanes lambda = kr_alpha_step_lanes(rows, uniform, velocity);
                  std::swap(rows.u, rows.u_next);
                  return lambda;
                },
                [&]() __attribute__((always_inline)) { return velocity; },
                [&]() __attribute__((always_inline)) {
                  return kr_alpha_energy_lanes(*b.mass, *b.stiffness, rows);
                },
                [&](int l) __attribute__((always_inline)) { set_lane(l, nullptr, nullptr); }));
}

// Whether a tridiagonal matrix's off-diagonals are one value, lower = upper, and its interior
// diagonal one value (the rod's).
bool uniform_symmetric(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  for (Eigen::Index i = 1; i < n; ++i) {
    if (a.lower[i] != a.lower[1] || a.upper[i - 1] != a.lower[1]) return false;
  }
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    if (a.diag[i] != a.diag[1]) return false;
  }
  return true;
}

// Lane l of a LaneDiagonals from a uniform symmetric matrix.
void set_diagonals(LaneDiagonals& d, int l, const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  d.first.set(l, a.diag[0]);
  d.interior.set(l, n > 2 ? a.diag[1] : 0.0);
  d.last.set(l, a.diag[n - 1]);
  d.off.set(l, n > 1 ? a.lower[1] : 0.0);
}

// Lane l of a factorisation's rows.
void set_factors(FactorRows& rows, int l, const TridiagonalFactorization& f) {
  const Eigen::VectorXd& upper = f.upper_ratios();
  const Eigen::Index n = f.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    rows.inverse_pivot[i].set(l, f.inverse_pivots()[i]);
    rows.minus_lower_ratio[i].set(l, -f.lower_ratios()[i]);
    rows.minus_upper_ratio[i].set(l, -upper[i]);
    // As TridiagonalFactorization::factor forms it.
    rows.upper_ratio2[i].set(l, i + 2 < n ? upper[i] * upper[i + 1] : 0.0);
  }
}

}  // namespace

bool kr_alpha_batchable(const RodScene& scene, const MethodParams& method) {
  // Damping adds a product with C to each half of the right-hand side: damped runs go through
  // simulate().
  return std::holds_alternative<KrAlphaParams>(method) && scene.rayleigh_mass == 0.0 &&
         scene.rayleigh_stiffness == 0.0;
}

void simulate_kr_alpha_batch(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             std::vector<LaneBlock>& storage,
                             std::array<State, kBatchLanes>& starts,
                             std::array<ContactTrace, kBatchLanes>& traces,
                             std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  SecondOrderSystem system = assemble_rod(scenes[0]);  // every lane's, its gap set per lane
  const Eigen::Index n = system.size();
  KrBatch b{};
  b.loop = loop_settings(scenes[0], options);
  const double dt = b.loop.dt;

  constexpr int kArrays = 3 * 4 + 9;  // three factorisations' four, the rows' nine below
  LaneStorage arrays(storage, kArrays, n);
  KrRows& rows = b.rows;
  rows.n = n;
  for (FactorRows* f : {&rows.mass, &rows.d, &rows.e}) {
    arrays.take(
        {&f->inverse_pivot, &f->minus_lower_ratio, &f->minus_upper_ratio, &f->upper_ratio2});
  }
  arrays.take({&rows.u, &rows.u_next, &rows.v_hat, &rows.a, &rows.r, &rows.y, &rows.w,
               &rows.a_response, &rows.w_response});
  KrConstants& constants = b.constants;
  rows.constants = &constants;
  constants.gap = splat(kInf);  // unused lanes never touch a wall
  constants.dt = splat(dt);
  b.mass = &system.mass;
  b.stiffness = &system.stiffness;
  b.start = &starts;

  // Every lane prepared first: the start changes a lane's start state (the contact at the start
  // corrects a), which a later lane of the same velocity would otherwise copy (prepare_lane).
  std::array<bool, kBatchLanes> prepared{};
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    prepared[lane] =
        prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, b.lanes[lane]);
  }
  // M's factorisation is every lane's; the kernel's rows are checked, not assumed (never otherwise
  // on a RodScene).
  TridiagonalFactorization mass;
  const bool mass_factored = mass.factor(system.mass);
  const bool uniform = uniform_symmetric(system.mass) && uniform_symmetric(system.stiffness) &&
                       system.contact_dof == n - 1 && n >= 2;
  rows.lumped_mass = mass_factored;
  for (Eigen::Index i = 0; i < n && mass_factored; ++i) {
    rows.lumped_mass = rows.lumped_mass && mass.lower_ratios()[i] == 0.0 &&
                       mass.upper_ratios()[i] == 0.0 && mass.inverse_pivots()[i] > 0.5;
  }
  bool any = false;
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    if (!prepared[lane]) continue;
    LaneRun& run = b.lanes[lane];
    RunSummary& summary = summaries[lane];
    const auto fail = [&](const std::string& message) {
      summary.status = RunStatus::failed;
      summary.message = message;
      run = LaneRun{};
    };
    if (!uniform) {
      fail("batched kernel: the mass or the stiffness is not uniform along the rod");
      continue;
    }
    if (!mass_factored) {
      fail("kr-alpha: singular mass matrix");
      continue;
    }
    // KrAlphaExplicit::initialize, by its expressions: the matrices D and E and their
    // factorisations.
    const KrAlphaCoefficients c = kr_alpha_coefficients(std::get<KrAlphaParams>(methods[lane]));
    system.gap = scenes[lane].gap;
    const double c_weight = c.gamma * dt, k_weight = c.beta * dt * dt;
    const Tridiagonal d_matrix = system.mass.combined(1.0, system.damping, c_weight)
                                     .combined(1.0, system.stiffness, k_weight);
    const Tridiagonal e_matrix =
        system.mass.combined(1.0 - c.alpha_m, system.damping, (1.0 - c.alpha_f) * c_weight)
            .combined(1.0, system.stiffness, (1.0 - c.alpha_f) * k_weight);
    TridiagonalFactorization d, e;
    if (!d.factor(d_matrix) || !e.factor(e_matrix)) {
      fail("kr-alpha: singular matrix M + gamma*dt*C + beta*dt^2*K");
      continue;
    }
    if (!uniform_symmetric(d_matrix)) {
      fail("batched kernel: the mass or the stiffness is not uniform along the rod");
      continue;
    }
    // The responses to a unit force on the contact dof (KrAlphaExplicit::respond): the start's
    // w = D⁻¹·f, the step's a = E⁻¹·D·M⁻¹·f and w = D⁻¹·M·a.
    const Eigen::Index contact = system.contact_dof;
    Eigen::VectorXd force = Eigen::VectorXd::Zero(n);
    force[contact] = 1.0;
    Eigen::VectorXd start_a = force;
    mass.solve_in_place(start_a);
    Eigen::VectorXd start_w = force;
    d.solve_in_place(start_w);
    Eigen::VectorXd step_a = force;
    mass.solve_in_place(step_a);
    Eigen::VectorXd y(n);
    d_matrix.multiply(step_a, y);
    e.solve_in_place(y);
    step_a = y;
    Eigen::VectorXd step_w(n);
    system.mass.multiply(step_a, step_w);
    d.solve_in_place(step_w);

    // The start: α1·a₀, u₂ = u₀ + Δt·v₀ + Δt²/2·α1·a₀ with the contact at the start
    // (KrAlphaExplicit::enforce, single wall), v̂₀ = v₀ − γΔt·α1·a₀.
    State& state = starts[lane];
    Eigen::VectorXd w(n);
    system.mass.multiply(state.a, w);
    d.solve_in_place(w);
    const double start_scale = 0.5 * dt * dt;
    KrStart& kr = b.kr_start[lane];
    kr.u_next = state.u + dt * state.v + start_scale * w;
    state.lambda = 0.0;
    if (system.has_contact() && kr.u_next[contact] > system.gap) {
      const double s = start_scale;
      const double lambda = (kr.u_next[contact] - system.gap) / (s * start_w[contact]);
      state.a -= lambda * start_a;
      w -= lambda * start_w;
      kr.u_next -= (s * lambda) * start_w;
      kr.u_next[contact] = system.gap;
      state.lambda = lambda;
    }
    const Eigen::VectorXd v_hat = state.v - (c.gamma * dt) * w;
    // Advanced by the first step's v̂ += Δt·w (KrRows).
    kr.v_hat = v_hat + dt * w;

    // The lane's constants, by KrAlphaExplicit::step's expressions.
    const double scale = dt * dt * (0.5 + c.gamma);
    constants.minus_af.set(l, -c.alpha_f);
    constants.minus_rest.set(l, -(1.0 - c.alpha_f));
    constants.scale.set(l, scale);
    constants.lead.set(l, c.gamma * dt);
    constants.contact_denominator.set(l, scale * step_w[contact]);
    constants.gap.set(l, system.has_contact() ? system.gap : kInf);
    set_factors(rows.mass, l, mass);
    set_factors(rows.d, l, d);
    set_factors(rows.e, l, e);
    for (Eigen::Index i = 0; i < n; ++i) {  // KrRows::lumped_mass
      rows.lumped_mass = rows.lumped_mass && d_matrix.diag[i] != 0.0 &&
                         e.inverse_pivots()[i] != 0.0 && (i == 0 || e.lower_ratios()[i] != 0.0);
    }
    set_diagonals(constants.stiffness, l, system.stiffness);
    set_diagonals(constants.mass_matrix, l, system.mass);
    set_diagonals(constants.d_matrix, l, d_matrix);
    for (Eigen::Index i = 0; i < n; ++i) {
      rows.a_response[i].set(l, step_a[i]);
      rows.w_response[i].set(l, step_w[i]);
    }
    any = true;
  }
  if (any) {
    // The rows of one value in every lane: within [1, n − 2) (the ends and the row before the last
    // are handled apart), beginning where every factor has reached the value of the row before
    // them.
    rows.uniform_begin = rows.uniform_end = 1;
    if (n >= 4) {
      rows.uniform_end = n - 2;
      const Eigen::Index ref = n - 3;
      const auto same = [&](const Lanes* x, Eigen::Index i) {  // bit for bit: −0 is not 0
        for (int l = 0; l < kBatchLanes; ++l) {
          if (std::bit_cast<std::uint64_t>(x[i][l]) != std::bit_cast<std::uint64_t>(x[ref][l])) {
            return false;
          }
        }
        return true;
      };
      const auto same_row = [&](Eigen::Index i) {
        for (const FactorRows* f : {&rows.mass, &rows.d, &rows.e}) {
          if (!same(f->inverse_pivot, i) || !same(f->minus_lower_ratio, i) ||
              !same(f->minus_upper_ratio, i) || !same(f->upper_ratio2, i)) {
            return false;
          }
        }
        return true;
      };
      rows.uniform_begin = ref;
      while (rows.uniform_begin > 1 && same_row(rows.uniform_begin - 1)) --rows.uniform_begin;
    }
    run_kr_alpha_batch(b);
  }
  finish_lanes(count, start, traces, summaries);
}

}  // namespace impactid
