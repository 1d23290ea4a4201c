#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <variant>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_kr_alpha.hpp"
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

// E's factorisation's numbers of a row in every lane: TridiagonalFactorization's 1/pivot,
// −lower/pivot, −upper/pivot (negated as the sweeps negate them) and the product of two upper
// ratios.
struct Factors {
  Lanes inverse_pivot, minus_lower_ratio, minus_upper_ratio, upper_ratio2;
};
// The same, [unknown][lane].
struct FactorRows {
  Lanes *inverse_pivot, *minus_lower_ratio, *minus_upper_ratio, *upper_ratio2;
};

// A tridiagonal matrix of the uniform rod in every lane: its first, interior and last diagonal
// entries and its off-diagonal (lower = upper, checked).
struct LaneDiagonals {
  Lanes first, interior, last, off;
};

// The step's constants of every lane, apart from KrRows: the step reads them through a pointer once
// a pass (each pass copies what it needs into registers), not in a copy of its own.
struct KrConstants {
  LaneDiagonals stiffness, d_matrix;
  Lanes dt, minus_af, minus_rest, scale, lead, contact_denominator, gap;
};

// What KrAlphaExplicit::step reads, for every lane. Small (the arrays' pointers and the bounds;
// the constants apart, in KrConstants), so that the step takes a local copy of it (see
// kr_alpha_step_lanes).
struct KrRows {
  Eigen::Index n;
  FactorRows e;
  // Rows [uniform_begin, uniform_end) have every factor of row uniform_begin in every lane, bit
  // for bit (checked): held in registers there. Within [1, n − 2).
  Eigen::Index uniform_begin, uniform_end;
  const KrConstants* constants;
  // The state: u (the sample's), u_next (u₂, fixed by the last equilibrium), v̂ already advanced by
  // Δt·w (the next step's first update, done at the end of this one), w = α1·a; y scratch.
  Lanes *u, *u_next, *v_hat, *w, *y;
  // The step's response of w to a unit force on the contact dof (KrAlphaExplicit's
  // step_response_.w_main, E⁻¹·f).
  Lanes* w_response;
};

[[gnu::always_inline]] inline Factors factors(const FactorRows& f, Eigen::Index i) {
  return {f.inverse_pivot[i], f.minus_lower_ratio[i], f.minus_upper_ratio[i], f.upper_ratio2[i]};
}
// Row j's diagonal entry of a matrix of the rod.
[[gnu::always_inline]] inline Lanes diagonal(const LaneDiagonals& m, Eigen::Index j,
                                             Eigen::Index last) {
  return j == 0 ? m.first : j == last ? m.last : m.interior;
}

// Calls row.template operator()<kGeneric>(i, f) for every row, upwards (kUp) or downwards, with
// the row's factors of E: from its arrays outside [uniform_begin, uniform_end) (kGeneric: the row
// may be an end row or the one before the last), `uniform` inside it (an interior row), a copy in
// registers.
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

// The rows of the right-hand side r = 0 + (−α_f)·K·u, then + (−(1 − α_f))·K·u₁
// (Tridiagonal::multiply_add's rows: (l·x₋ + d·x) + u·x₊, each off-diagonal product shared by two
// rows), asked for upwards, row 0 first: 6 mul 6 add. (K·u is the last step's K·u₁, formed again:
// keeping it in an array was no faster.) Never −0: r starts as +0 + x.
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

// The first pass, upwards: row i of r − D·w (r of RightHandSide; D·w by multiply_rows' operations,
// d·w_i fused onto the lower neighbour's product, then + the upper's) and E's forward sweep on it
// (TridiagonalFactorization::forward_in_place: y_0·(1/pivot_0), then
// y_i·(1/pivot_i) − (l_i/pivot_i)·y_{i−1}) into y. 8 mul 8 add/sub 2 FMA.
[[gnu::always_inline]] inline void residual_sweep_up(const KrRows& b, const Factors& uniform) {
  const Eigen::Index last = b.n - 1;
  RightHandSide rhs(b);
  const LaneDiagonals dm = b.constants->d_matrix;
  const Lanes* const w = b.w;
  Lanes x = w[0], p = dm.off * x, p_prev{};  // w_i, its product with the off-diagonal
  Lanes eliminated{};                        // y_{i−1}
  each_row<true>(
      b, b.e,
      uniform, [&]<bool kGeneric>(Eigen::Index i, const Factors& s) __attribute__((always_inline)) {
        Lanes x_next{}, p_next{};
        if (!(kGeneric && i == last)) {
          x_next = w[i + 1];
          p_next = dm.off * x_next;
        }
        const Lanes d = kGeneric ? diagonal(dm, i, last) : dm.interior;
        Lanes product;
        if (kGeneric && i == 0) {
          product = fma(d, x, p_next);
        } else if (kGeneric && i == last) {
          product = fma(d, x, p_prev);
        } else {
          product = fma(d, x, p_prev) + p_next;
        }
        Lanes y = (rhs.template row<kGeneric>(i) - product) * s.inverse_pivot;
        if (!(kGeneric && i == 0)) y = fma(s.minus_lower_ratio, eliminated, y);
        store(&b.y[i], y);
        eliminated = y;
        p_prev = p;
        x = x_next;
        p = p_next;
      });
}

// One step of KR-α in every lane (KrAlphaExplicit::step, single wall, no damping): the passes of
// the header. Returns λ of the equilibrium at t + Δt; `velocity` gets the contact dof's reported
// velocity v̂ + γΔt·w. Leaves u₁ in rows.u_next and u₂ in rows.u: the caller swaps them.
[[gnu::always_inline]] inline Lanes kr_alpha_step_lanes(const KrRows& rows, const Factors& uniform,
                                                        Lanes& velocity) {
  // A local copy of the pointers and bounds, so that the compiler keeps them in registers: a store
  // through a Lanes pointer (may_alias) could otherwise change them, and every use would reload
  // them (core/batch/rod_step.hpp's step_lanes). The constants (KrConstants) and `uniform` are
  // copied by each pass, as far as it uses them, into registers.
  const KrRows b = rows;
  const KrConstants& k = *b.constants;
  const Eigen::Index last = b.n - 1;

  // Up: r − D·w and E's forward sweep.
  residual_sweep_up(b, uniform);

  // The contact (the rod's contact dof is the last, where E's back substitution starts: x = y
  // there): the contact-free u₂ and λ, by KrAlphaExplicit::enforce's expressions.
  const Lanes* const u1 = b.u_next;
  Lanes* const u2 = b.u;  // u, no longer needed: u₂ is written over it
  const Lanes dt = k.dt, scale = k.scale, gap = k.gap, lead = k.lead;
  const Lanes free_end = (u1[last] + dt * b.v_hat[last]) + scale * (b.w[last] + b.y[last]);
  const LaneMask closes = greater(free_end, gap);
  const bool any = any_lane(closes);
  Lanes lambda{}, scaled{};
  if (any) {
    lambda = select(closes, (free_end - gap) / k.contact_denominator, Lanes{});
    scaled = scale * lambda;
  }
  // Down: E's back substitution, w += x, u₂ = (u₁ + Δt·v̂) + s·w, the contact's corrections,
  // v̂ += Δt·w: 3 mul 4 add 2 FMA.
  const auto solve = [&]<bool kContact>() __attribute__((always_inline)) {
    solve_down(
        b, b.e, uniform,
        b.y, [&]<bool kGeneric>(Eigen::Index i, const Lanes& x) __attribute__((always_inline)) {
          const Lanes v_hat = b.v_hat[i];
          Lanes w = b.w[i] + x;
          Lanes next = (u1[i] + dt * v_hat) + scale * w;
          if constexpr (kContact) {
            const Lanes response = b.w_response[i];
            w = select(closes, w - lambda * response, w);
            next = select(closes, next - scaled * response, next);
          }
          if (kGeneric && i == last) {
            next = select(closes, gap, next);  // exactly the wall, not a few ulps off
            velocity = v_hat + lead * w;
          }
          store(&b.w[i], w);
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

// Each lane's start as KrAlphaExplicit::initialize leaves it: u₂, v̂ (already advanced by Δt·w,
// see KrRows) and w = α1·a₀; u and λ are in the lane's State.
struct KrStart {
  Eigen::VectorXd u_next, v_hat, w;
};

struct KrBatch {
  KrRows rows;
  KrConstants constants;
  const Tridiagonal *mass, *stiffness;
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;
  std::array<KrStart, kLanes> kr_start;
  LaneLoop loop;
};

// The batch loop (core/batch/batch_lanes.hpp: run_lanes) with KR-α's step: everything the loop
// calls is inlined.
void run_kr_alpha_batch(KrBatch& b) {
  KrRows& rows = b.rows;
  const Factors uniform = factors(rows.e, rows.uniform_begin);
  const Eigen::Index n = rows.n;
  Lanes velocity{};
  const auto set_lane = [&](int l, const State* start, const KrStart* kr)
      __attribute__((always_inline)) {
    for (Eigen::Index i = 0; i < n; ++i) {
      rows.u[i].set(l, start ? start->u[i] : 0.0);
      rows.u_next[i].set(l, kr ? kr->u_next[i] : 0.0);
      rows.v_hat[i].set(l, kr ? kr->v_hat[i] : 0.0);
      rows.w[i].set(l, kr ? kr->w[i] : 0.0);
    }
  };
  run_lanes(b.lanes, b.loop,
            lane_stepper(
                [&](int l) __attribute__((always_inline)) {
                  const auto lane = static_cast<std::size_t>(l);
                  const State& start = b.start[lane];
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

namespace {

// One sub-batch (at most kLanes runs) of KR-α.
void simulate_kr_alpha_sub_batch(std::span<const RodScene> scenes,
                                 std::span<const MethodParams> methods, const RunOptions& options,
                                 std::vector<LaneBlock>& storage, LaneSpan<State> starts,
                                 LaneSpan<ContactTrace> traces, std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  SecondOrderSystem system = assemble_rod(scenes[0]);  // every lane's, its gap set per lane
  const Eigen::Index n = system.size();
  KrBatch b{};
  b.loop = loop_settings(scenes[0], options);
  const double dt = b.loop.dt;

  constexpr int kArrays = 4 + 6;  // E's factorisation's four, the rows' six below
  LaneStorage arrays(storage, kArrays, n);
  KrRows& rows = b.rows;
  rows.n = n;
  arrays.take({&rows.e.inverse_pivot, &rows.e.minus_lower_ratio, &rows.e.minus_upper_ratio,
               &rows.e.upper_ratio2});
  arrays.take({&rows.u, &rows.u_next, &rows.v_hat, &rows.w, &rows.y, &rows.w_response});
  KrConstants& constants = b.constants;
  rows.constants = &constants;
  constants.gap = splat(kInf);  // unused lanes never touch a wall
  constants.dt = splat(dt);
  b.mass = &system.mass;
  b.stiffness = &system.stiffness;
  b.start = starts.data();

  // Every lane prepared first, then set up (the start's contact below changes only the lane's
  // own λ and KrStart, not the acceleration a later lane of the same velocity copies).
  std::array<bool, kLanes> prepared{};
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    prepared[lane] =
        prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, b.lanes[lane]);
  }
  // M is factored only to fail as KrAlphaExplicit::initialize does on a singular one (no step
  // solves with it); the kernel's rows are checked, not assumed (never otherwise on a RodScene).
  const bool mass_factored = TridiagonalFactorization{}.factor(system.mass);
  const bool uniform = uniform_symmetric(system.mass) && uniform_symmetric(system.stiffness) &&
                       system.contact_dof == n - 1 && n >= 2;
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
    const auto c = std::get<KrAlphaCoefficients>(stepper_coefficients(methods[lane]));
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
    // The responses of w to a unit force on the contact dof (KrAlphaExplicit::respond): the
    // start's D⁻¹·f, the step's E⁻¹·f. (The start's acceleration, which the scalar stepper also
    // corrects, is not what a batch reports.)
    const Eigen::Index contact = system.contact_dof;
    Eigen::VectorXd force = Eigen::VectorXd::Zero(n);
    force[contact] = 1.0;
    Eigen::VectorXd start_w = force;
    d.solve_in_place(start_w);
    Eigen::VectorXd step_w = force;
    e.solve_in_place(step_w);

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
      w -= lambda * start_w;
      kr.u_next -= (s * lambda) * start_w;
      kr.u_next[contact] = system.gap;
      state.lambda = lambda;
    }
    const Eigen::VectorXd v_hat = state.v - (c.gamma * dt) * w;
    // Advanced by the first step's v̂ += Δt·w (KrRows).
    kr.v_hat = v_hat + dt * w;
    kr.w = w;

    // The lane's constants, by KrAlphaExplicit::step's expressions.
    const double scale = dt * dt * (0.5 + c.gamma);
    constants.minus_af.set(l, -c.alpha_f);
    constants.minus_rest.set(l, -(1.0 - c.alpha_f));
    constants.scale.set(l, scale);
    constants.lead.set(l, c.gamma * dt);
    constants.contact_denominator.set(l, scale * step_w[contact]);
    constants.gap.set(l, system.has_contact() ? system.gap : kInf);
    set_factors(rows.e, l, e);
    set_diagonals(constants.stiffness, l, system.stiffness);
    set_diagonals(constants.d_matrix, l, d_matrix);
    for (Eigen::Index i = 0; i < n; ++i) rows.w_response[i].set(l, step_w[i]);
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
        for (int l = 0; l < kLanes; ++l) {
          if (std::bit_cast<std::uint64_t>(x[i][l]) != std::bit_cast<std::uint64_t>(x[ref][l])) {
            return false;
          }
        }
        return true;
      };
      const auto same_row = [&](Eigen::Index i) {
        const FactorRows& f = rows.e;
        return same(f.inverse_pivot, i) && same(f.minus_lower_ratio, i) &&
               same(f.minus_upper_ratio, i) && same(f.upper_ratio2, i);
      };
      rows.uniform_begin = ref;
      while (rows.uniform_begin > 1 && same_row(rows.uniform_begin - 1)) --rows.uniform_begin;
    }
    run_kr_alpha_batch(b);
  }
  finish_lanes(count, start, traces, summaries);
}

}  // namespace

void simulate_kr_alpha_lanes(std::span<const RodScene> scenes,
                             std::span<const MethodParams> methods, const RunOptions& options,
                             BatchStorage workspace, std::span<RunSummary> summaries) {
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    simulate_kr_alpha_sub_batch(scenes.subspan(first, count), methods.subspan(first, count),
                                options, workspace.blocks, sub_batch_part(workspace.starts, first),
                                sub_batch_part(workspace.traces, first),
                                summaries.subspan(first, count));
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
