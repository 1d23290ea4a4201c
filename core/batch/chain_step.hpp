// The implicit step of a chain of bodies lane by lane (core/methods/implicit_integrator.hpp:
// ImplicitIntegrator::step with its contacts' rows): the contacts, the lanes' arrays and
// coefficients, step_chain and the energy after it. Why and how: core/batch/batched_chain.hpp.
//
// Part of core/batch/chain_kernel.cpp, which includes it after core/batch/kernel_target.hpp, as one
// translation unit with it: so the compiler inlines these functions into the kernel's loops as it
// did when they were one file (the same machine code). It includes only core/batch/ headers: the
// kernel file includes every other header first, before the level's target, so that their functions
// keep the baseline target.
#pragma once

#include "core/batch/simd_lanes.hpp"

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {  // NOLINT(google-build-namespaces): one translation unit (above)

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

// One contact of the chain: its nodes and probe (the same in every lane), each lane's gap and
// column A⁻¹·G_kᵀ. A lane's column is exactly zero outside its rows [lane_begin, lane_end)
// (ImplicitIntegrator::constraint_rows), where the scalar step does not touch the unknowns; the
// rows differ between lanes only where a column decays to an underflow, so the correction runs
// vectorised over the rows every lane shares and lane by lane over the others.
//
// Every struct holding Lanes in memory is aligned as LaneBlock: the vector type's own alignment is
// that of the baseline target (16 bytes) where it is declared, while the AVX-512 version of the
// kernel loads it with instructions that need 64.
struct alignas(LaneBlock) LaneContact {
  Eigen::Index plus = -1, minus = -1;
  Lanes gap;
  Lanes area;  // the probe's, in every lane: pressure = λ/area
  Eigen::Index velocity_dof = 0;
  Lanes* influence = nullptr;                     // rows [begin, end): influence[i − begin]
  Eigen::Index begin = 0, end = 0;                // the union of the lanes' rows
  Eigen::Index common_begin = 0, common_end = 0;  // their intersection (possibly empty)
  std::array<Eigen::Index, kLanes> lane_begin{}, lane_end{};
};

// A contact force entering the right-hand side of a row: rhs[row] −= force (the contact's plus
// node) or += force (its minus node). Sorted by row, then contact: the scalar order.
struct ForceRow {
  Eigen::Index row;
  int contact;
  bool plus;
};

// Each lane's copy of the scalar step's constants, computed by the same expressions
// (ImplicitIntegrator: dt2 * c_.b0 is (Δt·Δt)·b0, c_.b1 * dt2 is b1·(Δt·Δt), and the violation's
// c_.b1 * dt * dt is (b1·Δt)·Δt).
struct alignas(LaneBlock) ChainCoefficients {
  double dt;
  Lanes dt2_b0, dt_g0, af, b1_dt2, g1_dt, b1_dt_dt, minus_am, one_minus_w, w;
  LaneMask mass_term;    // α_m ≠ 0: the scalar step adds −α_m·M·a only then
  LaneMask plain_state;  // lanes that start at this sample: every row holds u, v, a as they are
};

// A run of the rows 1 .. n − 3 (those between the first row and the last two), as the sweeps'
// loops take them; the runs tile those rows in order. `forces`: one row that takes a contact
// force. `uniform`: every row of the run has the same row of K and, in every lane, the same
// factors, bit for bit, as its first: in a uniform segment the pivots converge to a fixed point
// after some rows, and from there the loops hold K's row and the factors in registers instead
// of reading them at every row (the rod's kernel does the same with its converged tail).
struct alignas(LaneBlock) RowBlock {
  Eigen::Index begin = 0, end = 0;
  bool forces = false, uniform = false;
  double k_lower = 0.0, k_diag = 0.0, k_upper = 0.0;
  Lanes minus_inverse_pivot, minus_lower_ratio, minus_upper_ratio;
};

struct alignas(LaneBlock) ChainArrays {
  Eigen::Index n;
  const Tridiagonal* stiffness;
  const Tridiagonal* damping;
  const Tridiagonal* mass;
  // The state: rows 0 and n − 1 hold u, v, a; the others u*, v* and a (the deferred update).
  Lanes *u, *v, *a;
  // Each lane's factorisation: TridiagonalFactorization's arrays, negated as the sweeps use them
  // (a negation is exact: the same bits as negating at every step).
  Lanes *minus_inverse_pivot, *minus_lower_ratio, *minus_upper_ratio;
  int m;
  LaneContact* contacts;
  const ForceRow* force_rows;  // 2·m at most
  int force_row_count;
  const RowBlock* blocks;
  int block_count;
  std::array<const double*, kLanes> delassus;  // each lane's m×m, column-major
  Lanes single_delassus;  // with one contact (m = 1): each lane's 1×1 Delassus matrix
};

// The contact corrections a −= w·λ_k·A⁻¹·G_kᵀ of the last step that the rows 1 .. n − 2 still
// await, in contact order. Like the update, the correction is deferred to the next forward
// sweep, which reads a anyway: the same operations on the same numbers, but the correction pass
// then neither loads nor stores a; what reads a row before that (the samples, the energy) applies
// them on the way (corrected). Deferred only when every lane's column has the same rows (the
// usual case: LaneContact::common_begin/end); otherwise applied at once.
struct alignas(LaneBlock) PendingCorrections {
  int count = 0;
  std::array<int, kMaxConstraints> contact{};
  std::array<Lanes, kMaxConstraints> force;
  std::array<LaneMask, kMaxConstraints> on;
};

// Row i's acceleration `a` with the pending corrections applied (apply_constraint_forces'
// operations, in its order).
[[gnu::always_inline]] inline Lanes corrected(const ChainArrays& x, const PendingCorrections& p,
                                              Eigen::Index i, const Lanes& row) {
  Lanes a = row;  // by reference: a vector by value draws GCC's note on its calling convention
  for (int q = 0; q < p.count; ++q) {
    const LaneContact& k = x.contacts[p.contact[q]];
    if (i >= k.common_begin && i < k.common_end) {
      a = select(p.on[q], a - p.force[q] * k.influence[i - k.begin], a);
    }
  }
  return a;
}

// One implicit step of every lane: ImplicitIntegrator::predict and ::step_constraints, lane by
// lane the same operations. multipliers[k] holds contact k's λ of every lane, on entry at t and
// on return at t + Δt; `pending` the corrections the previous step deferred (kCorrect: some),
// on return this step's.
template <bool kDamping, bool kMassTerm, bool kStartingLanes, bool kCorrect>
[[gnu::always_inline]] inline void step_chain(const ChainArrays& arrays, const ChainCoefficients& c,
                                              Lanes* multipliers, PendingCorrections& pending) {
  // Local copies, kept in registers (Lanes stores may alias anything): see the rod's kernel.
  const ChainArrays x = arrays;
  const Eigen::Index n = x.n, last = n - 1;
  const Diagonals K(*x.stiffness);
  const Diagonals C(kDamping ? *x.damping : *x.stiffness);
  const Diagonals M(*x.mass);
  const Lanes dt = splat(c.dt);
  const Lanes minus_af = -c.af;

  // Predictors u*, v* (stored over u, v) and the α_f-weighted u, v of row i.
  struct Weighted {
    Lanes u, v, a;
  };
  const auto predict = [&]<bool kPlainRow>(Eigen::Index i) __attribute__((always_inline)) {
    const Lanes a = kCorrect && !kPlainRow ? corrected(x, pending, i, x.a[i]) : x.a[i];
    const WeightedRow weighted =
        predict_row<!kPlainRow, kStartingLanes, kDamping>(c, dt, minus_af, &x.u[i], &x.v[i], a);
    Weighted w;
    w.u = weighted.u;
    if constexpr (kDamping) w.v = weighted.v;
    if constexpr (kMassTerm) w.a = a;
    return w;
  };

  // rhs = −K·u_w − C·v_w − α_m·M·a − (1−w)·Gᵀ·λ, then the forward sweep of the solve.
  Weighted prev{}, cur = predict.template operator()<true>(0), next{};
  Lanes eliminated{};
  int force = 0;
  // Row i; kForces: the row may take a contact force (the first and the last row, and the blocks
  // of one forced row); kUniform: K's row and the factors are the block's (RowBlock), not read.
  const auto
      forward = [&]<bool kFirst, bool kLast, bool kNextIsLast, bool kForces, bool kUniform = false>(
          Eigen::Index i, const RowBlock* block = nullptr) __attribute__((always_inline)) {
    if constexpr (!kLast) next = predict.template operator()<kNextIsLast>(i + 1);
    Lanes stiffness;  // K·u_w's row, as Tridiagonal::multiply forms it
    if constexpr (kFirst) {
      stiffness = fma(splat(K.diag[i]), cur.u, splat(K.upper[i]) * next.u);
    } else if constexpr (kLast) {
      stiffness = fma(splat(K.diag[i]), cur.u, splat(K.lower[i]) * prev.u);
    } else if constexpr (kUniform) {
      stiffness = fma(splat(block->k_diag), cur.u, splat(block->k_lower) * prev.u) +
                  splat(block->k_upper) * next.u;
    } else {
      stiffness =
          fma(splat(K.diag[i]), cur.u, splat(K.lower[i]) * prev.u) + splat(K.upper[i]) * next.u;
    }
    const Lanes minus_inverse_pivot =
        kUniform ? block->minus_inverse_pivot : x.minus_inverse_pivot[i];
    // The array holds −1/pivot. With K's term alone in the right-hand side, −K·u's sign goes onto
    // it: (−s)·p = s·(−p) exactly, one instruction fewer in the common row.
    Lanes scaled;
    if constexpr (!kDamping && !kMassTerm && !kForces) {
      scaled = stiffness * minus_inverse_pivot;
    } else {
      Lanes r = -stiffness;
      if constexpr (kDamping) r = r + -1.0 * row<kFirst, kLast>(C, i, prev.v, cur.v, next.v);
      if constexpr (kMassTerm) {
        r = select(c.mass_term, r + c.minus_am * row<kFirst, kLast>(M, i, prev.a, cur.a, next.a),
                   r);
      }
      if constexpr (kForces) {
        for (; force < x.force_row_count && x.force_rows[force].row == i; ++force) {
          const ForceRow& f = x.force_rows[force];
          const Lanes weighted = c.one_minus_w * multipliers[f.contact];
          r = select(nonzero(weighted), f.plus ? r - weighted : r + weighted, r);
        }
      }
      scaled = r * -minus_inverse_pivot;
    }
    Lanes y = scaled;
    if constexpr (!kFirst) {
      y = fma(kUniform ? block->minus_lower_ratio : x.minus_lower_ratio[i], eliminated, scaled);
    }
    store(&x.a[i], y);
    eliminated = y;
    prev = cur;
    cur = next;
  };
  forward.template operator()<true, false, false, true>(0);
  for (int b = 0; b < x.block_count; ++b) {
    // A copy, so that its values stay in registers across the block's rows.
    const RowBlock block = x.blocks[b];
    if (block.forces) {
      forward.template operator()<false, false, false, true>(block.begin);
    } else if (block.uniform) {
      for (Eigen::Index i = block.begin; i < block.end; ++i) {
        forward.template operator()<false, false, false, false, true>(i, &block);
      }
    } else {
      for (Eigen::Index i = block.begin; i < block.end; ++i) {
        forward.template operator()<false, false, false, false>(i);
      }
    }
  }
  forward.template operator()<false, false, true, true>(last - 1);
  forward.template operator()<false, true, false, true>(last);

  // Back substitution, two rows at a time as TridiagonalFactorization::backward_in_place, with
  // its products c'_i·c'_{i+1} formed again from the negated ratios ((−a)·(−b) = a·b exactly):
  // one array fewer to stream through the cache. In a uniform block both ratios are the block's
  // but in its last row (whose c'_{i+1} is the next block's).
  Lanes x1 = x.a[last];  // x_{i+1}
  Lanes y_next = x.a[last - 1];
  Lanes x2 = x1;  // x_{i+2}
  Lanes ratio_next = x.minus_upper_ratio[last - 1];
  x1 = fma(ratio_next, x1, y_next);
  store(&x.a[last - 1], x1);
  const auto backward = [&](Eigen::Index i, const Lanes& ratio, const Lanes& ratio2)
      __attribute__((always_inline)) {
    const Lanes y = x.a[i];
    const Lanes solved = fma(ratio2, x2, fma(ratio, y_next, y));
    store(&x.a[i], solved);
    y_next = y;
    x2 = x1;
    x1 = solved;
    ratio_next = ratio;
  };
  for (int b = x.block_count - 1; b >= 0; --b) {
    const RowBlock& block = x.blocks[b];
    Eigen::Index i = block.end - 1;
    if (block.uniform) {
      const Lanes ratio = block.minus_upper_ratio;
      backward(i, ratio, ratio * ratio_next);
      const Lanes ratio2 = ratio * ratio;
      for (--i; i >= block.begin; --i) backward(i, ratio, ratio2);
    } else {
      for (; i >= block.begin; --i) {
        const Lanes ratio = x.minus_upper_ratio[i];
        backward(i, ratio, ratio * ratio_next);
      }
    }
  }
  {
    const Lanes ratio = x.minus_upper_ratio[0];
    backward(0, ratio, ratio * ratio_next);
  }

  // The violations of the contact-free prediction, u_free formed as the scalar step forms it.
  const int m = x.m;
  std::array<Lanes, kMaxConstraints> violation, weighted;
  LaneMask penetrating{};
  for (int j = 0; j < m; ++j) {
    const LaneContact& k = x.contacts[j];
    Lanes g = -k.gap;
    if (k.plus >= 0) g = g + fma(c.b1_dt_dt, x.a[k.plus], x.u[k.plus]);
    if (k.minus >= 0) g = g - fma(c.b1_dt_dt, x.a[k.minus], x.u[k.minus]);
    violation[j] = g;
    weighted[j] = Lanes{};
    const LaneMask closes = greater(g, Lanes{});
    penetrating = penetrating | closes;
  }
  // The contact problem, in the lanes where a contact would penetrate: solve_contact_lcp's
  // answer is zero in the others (its start, the penetrating set, is empty and stays so).
  if (m == 1) {
    // One contact: solve_contact_lcp's answer is p/d where p > 0 (and d > 0, which a Delassus
    // matrix is), the same division, in every lane at once.
    const LaneMask solves = greater(x.single_delassus, Lanes{});
    const LaneMask on = penetrating & solves;
    weighted[0] = select(on, violation[0] / x.single_delassus, Lanes{});
  } else if (any_lane(penetrating)) {
    for (int l = 0; l < kLanes; ++l) {
      if (!penetrating[l]) continue;
      std::array<double, kMaxConstraints> p, mu;
      for (int j = 0; j < m; ++j) p[j] = violation[j][l];
      solve_contact_lcp(x.delassus[l], p.data(), m, mu.data());
      for (int j = 0; j < m; ++j) weighted[j].set(l, mu[j]);
    }
  }
  // a −= Σ_k w·λ_k·A⁻¹·G_kᵀ in contact order (apply_constraint_forces): deferred for the rows
  // 1 .. n − 2 when every lane's columns have the same rows, at once otherwise.
  pending.count = 0;
  bool defer = true;
  for (int j = 0; j < m; ++j) {
    const LaneContact& k = x.contacts[j];
    const LaneMask on = nonzero(weighted[j]);
    if (!any_lane(on)) continue;
    defer = defer && k.begin == k.common_begin && k.end == k.common_end;
    pending.contact[pending.count] = j;
    pending.force[pending.count] = weighted[j];
    pending.on[pending.count] = on;
    ++pending.count;
  }
  if (defer) {
    for (const Eigen::Index i : {Eigen::Index{0}, last}) {
      store(&x.a[i], corrected(x, pending, i, x.a[i]));
    }
  } else {
    for (int q = 0; q < pending.count; ++q) {
      const Lanes f = pending.force[q];
      const LaneMask on = pending.on[q];
      const LaneContact& k = x.contacts[pending.contact[q]];
      // Locals: a store through Lanes* may alias k, whose fields would be reloaded at every row.
      const Lanes* column = k.influence - k.begin;
      Lanes* a = x.a;
      for (Eigen::Index i = k.common_begin, end = k.common_end; i < end; ++i) {
        store(&a[i], select(on, a[i] - f * column[i], a[i]));
      }
      const auto lane_by_lane = [&](Eigen::Index from, Eigen::Index to) {
        for (Eigen::Index i = from; i < to; ++i) {
          for (int l = 0; l < kLanes; ++l) {
            if (on[l] && i >= k.lane_begin[l] && i < k.lane_end[l]) {
              x.a[i].set(l, x.a[i][l] - f[l] * k.influence[i - k.begin][l]);
            }
          }
        }
      };
      lane_by_lane(k.begin, k.common_begin);
      lane_by_lane(k.common_end, k.end);
    }
    pending.count = 0;
  }
  // The update of the first and the last row (the others' is deferred), the multipliers, and
  // a wall's node put exactly on its wall where the wall pushes (snap_walls).
  for (const Eigen::Index i : {Eigen::Index{0}, last}) {
    store(&x.u[i], fma(c.b1_dt2, x.a[i], x.u[i]));
    store(&x.v[i], fma(c.g1_dt, x.a[i], x.v[i]));
  }
  for (int j = 0; j < m; ++j) {
    const LaneContact& k = x.contacts[j];
    multipliers[j] = weighted[j] / c.w;
    const LaneMask pushes = greater(weighted[j], Lanes{});
    if (k.minus < 0) store(&x.u[k.plus], select(pushes, k.gap, x.u[k.plus]));
    if (k.plus < 0) store(&x.u[k.minus], select(pushes, -k.gap, x.u[k.minus]));
  }
}

// Row i's u and v at the end of a step (the first and the last row hold them; the others u*,
// v* and a, whose correction and update the next step would do with these operations).
[[gnu::always_inline]] inline Lanes displacement(const ChainArrays& x, const ChainCoefficients& c,
                                                 const PendingCorrections& p, Eigen::Index i) {
  if (i == 0 || i == x.n - 1) return x.u[i];
  return fma(c.b1_dt2, corrected(x, p, i, x.a[i]), x.u[i]);
}
[[gnu::always_inline]] inline Lanes velocity(const ChainArrays& x, const ChainCoefficients& c,
                                             const PendingCorrections& p, Eigen::Index i) {
  if (i == 0 || i == x.n - 1) return x.v[i];
  return fma(c.g1_dt, corrected(x, p, i, x.a[i]), x.v[i]);
}

// ½·vᵀMv + ½·uᵀKu of every lane after step_chain, each form summed in
// Tridiagonal::quadratic_form's order (as SecondOrderSystem::energy), with the rows' pending
// corrections applied as the next step will apply them.
[[gnu::always_inline]] inline Lanes chain_energy(const ChainArrays& x, const ChainCoefficients& c,
                                                 const PendingCorrections& p) {
  const Eigen::Index n = x.n;
  Lanes kinetic{}, strain{};
  Lanes u_prev{}, v_prev{}, u = displacement(x, c, p, 0), v = velocity(x, c, p, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes u_next{}, v_next{};
    if (i + 1 < n) u_next = displacement(x, c, p, i + 1), v_next = velocity(x, c, p, i + 1);
    kinetic = kinetic + v * quadratic_form_row(*x.mass, i, v_prev, v, v_next);
    strain = strain + u * quadratic_form_row(*x.stiffness, i, u_prev, u, u_next);
    u_prev = u, v_prev = v, u = u_next, v = v_next;
  }
  return 0.5 * kinetic + 0.5 * strain;
}

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
