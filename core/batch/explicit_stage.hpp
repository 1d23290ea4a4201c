// What the rod's two explicit stage schemes share (Noh–Bathe's, core/batch/noh_bathe_kernel.hpp,
// and Kim's, core/batch/kim_kernel.hpp): the rows of their solves M·a = −K·u, the forward pass of
// a solve, the plain energy, the batch, its loop and its set-up, each scheme supplying its rows,
// coefficients and step as a Scheme (NohBatheLanes, KimLanes).
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

// simulate_explicit_batch for an explicit stage scheme (Scheme: NohBatheLanes, KimLanes), with the
// workspace's storage, start states and traces. M's factorisation and M⁻¹·e_c
// (ExplicitStageContact::initialize's) are every lane's: one rod. Each lane is started as
// simulate() starts it (run_two_stage_explicit in core/run/simulation.cpp): the scheme's initialize
// with the lane's p and gap, the stable step and its warning.
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
                            lagrange_law().law);
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

}  // namespace
}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
