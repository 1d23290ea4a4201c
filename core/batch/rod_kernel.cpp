#include <Eigen/Core>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/batch/batched_kr_alpha.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/model/second_order_system.hpp"

// Last: the level's target for the rest of the file (core/batch/kernel_target.hpp), then the lane
// vocabulary and this kernel's parts (rod_step.hpp, rod_step_kinds.hpp: headers of this file alone,
// so that the kernel stays one translation unit), compiled for the level (kept in this order:
// clang-format would sort them).
// clang-format off
#include "core/batch/kernel_target.hpp"
#include "core/batch/batch_lanes.hpp"
#include "core/batch/simd_lanes.hpp"
#include "core/batch/rod_step.hpp"
#include "core/batch/rod_step_kinds.hpp"
// clang-format on

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

using StepKind = BatchStepKind;
constexpr auto step_kind = batch_step_kind;

struct Batch {
  LaneArrays arrays;
  // The single-step method's; a composite's second sub-step's; Wilson-θ's Δt and wall gap.
  LaneCoefficients coefficients;
  // The composite schemes and Wilson-θ only: the first sub-step's (Wilson-θ: the extended
  // step's) coefficients and its state (arrays: the mid state and that step's factorisation);
  // the composites' predictor weights, Wilson-θ's constants.
  StepKind kind;
  LaneArrays mid;
  LaneCoefficients first;
  CompositeLanes weights;
  WilsonLanes wilson;
  HouboltLanes houbolt;  // Houbolt only
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;
  LaneLoop loop;
};

void set_lane(const LaneArrays& x, int lane, const State* state) {
  set_lane_state(x.u, x.v, x.a, x.n, lane, state);
}

// The batch loop (core/batch/batch_lanes.hpp: run_lanes) with the implicit, composite, Wilson-θ or
// Houbolt step.
template <bool kDamping, bool kMassTerm, StepKind kKind>
[[gnu::always_inline]] inline void run_batch(Batch& b) {
  const LaneArrays& x = b.arrays;
  // A local copy, taken once: the compiler then knows that the step's stores through Lanes
  // pointers (may_alias) cannot change it, and keeps its fields in registers. Referred to in
  // Batch, every field was reloaded after every store; copied at every step, the copy itself
  // took a share of the batch's time (the figures are in the git log).
  LaneCoefficients c = b.coefficients;
  LaneCoefficients first = b.first;  // composite and Wilson-θ only, as the three below
  const CompositeLanes weights = b.weights;
  const WilsonLanes wilson = b.wilson;
  const LaneArrays mid = b.mid;
  // Houbolt only: the past displacements (swapped at every step), each lane's place in the
  // start-up: 0 and 1, its first and second step next; 2, Houbolt's step next, its coefficients
  // still the second step's; 3, Houbolt's step with its own (every lane that is not stepping).
  const HouboltLanes& houbolt = b.houbolt;
  Lanes *back1 = houbolt.back1, *back2 = houbolt.back2;
  std::array<int, kLanes> phase;
  phase.fill(3);
  bool startup = false;
  const Eigen::Index contact = x.n - 1;
  run_lanes(
      b.lanes, b.loop,
      lane_stepper(
          [&](int l) __attribute__((always_inline)) {
            const State& start = b.start[static_cast<std::size_t>(l)];
            set_lane(x, l, &start);
            c.plain_state.set(l, true);
            if constexpr (kKind == StepKind::houbolt) {
              phase[static_cast<std::size_t>(l)] = 0;
              startup = true;
              use_houbolt_step(x, houbolt, 0, l, c);
            }
            return LaneStart{.lambda = start.lambda, .t = start.t};
          },
          [&](bool starting, const Lanes& lambda) __attribute__((always_inline)) {
            Lanes next;
            if constexpr (kKind == StepKind::houbolt) {
              if (startup) {
                LaneMask phase0{}, phase1{};
                for (int l = 0; l < kLanes; ++l) {
                  phase0.set(l, phase[static_cast<std::size_t>(l)] == 0);
                  phase1.set(l, phase[static_cast<std::size_t>(l)] == 1);
                }
                if (starting) {
                  houbolt_predict_lanes<true, true>(x, c, houbolt, back1, back2, phase0, phase1);
                } else {
                  houbolt_predict_lanes<false, true>(x, c, houbolt, back1, back2, phase0, phase1);
                }
                // The state at t is formed (with the previous step's coefficients): lanes in
                // their second step or entering Houbolt's take this step's.
                startup = false;
                for (int l = 0; l < kLanes; ++l) {
                  int& p = phase[static_cast<std::size_t>(l)];
                  if (p == 1 || p == 2) use_houbolt_step(x, houbolt, p, l, c);
                  if (p < 3) ++p;
                  startup = startup || p < 3;
                }
              } else {
                houbolt_predict_lanes<false, false>(x, c, houbolt, back1, back2, LaneMask{},
                                                    LaneMask{});
              }
              std::swap(back1, back2);
              c.plain_state = LaneMask{};
              next = step_lanes<kDamping, false, false, true>(x, c, lambda);
            } else if constexpr (kKind == StepKind::wilson_theta) {  // plain rows
              next = wilson_theta_step_lanes<kDamping>(x, mid, first, c, wilson, lambda);
            } else if constexpr (kKind == StepKind::composite) {
              if (starting) {
                next = composite_step_lanes<kDamping, true>(x, mid, first, c, weights, lambda);
                c.plain_state = LaneMask{};
              } else {
                next = composite_step_lanes<kDamping, false>(x, mid, first, c, weights, lambda);
              }
            } else if (starting) {
              next = step_lanes<kDamping, kMassTerm, true>(x, c, lambda);
              c.plain_state = LaneMask{};
            } else {
              next = step_lanes<kDamping, kMassTerm, false>(x, c, lambda);
            }
            return next;
          },
          [&]() __attribute__((always_inline)) { return x.v[contact]; },
          [&]() __attribute__((always_inline)) {
            return lane_energy<kKind == StepKind::wilson_theta>(x, c);
          },
          [&](int l) __attribute__((always_inline)) {
            set_lane(x, l, nullptr);
            if constexpr (kKind == StepKind::houbolt) {
              set_lane_state(back1, back2, houbolt.start_velocity, x.n, l, nullptr);
            }
          }));
}

// One function per step kind: in one function holding every kind's loops, GCC optimised the
// composite and α_m loops worse once Wilson-θ's kind was added beside them (the figures are in the
// git log).
void run_composite_batch(Batch& b) {  // both sub-steps have α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::composite>(b);
  } else {
    run_batch<false, false, StepKind::composite>(b);
  }
}

void run_houbolt_batch(Batch& b) {  // its three steps have α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::houbolt>(b);
  } else {
    run_batch<false, false, StepKind::houbolt>(b);
  }
}

void run_wilson_theta_batch(Batch& b) {  // the extended step: α_m = 0
  if (b.arrays.damping != nullptr) {
    run_batch<true, false, StepKind::wilson_theta>(b);
  } else {
    run_batch<false, false, StepKind::wilson_theta>(b);
  }
}

void run_single_step_batch(Batch& b) {
  with_kernel_flags(
      b.arrays.damping != nullptr, any_lane(b.coefficients.mass_term),
      [&b]<bool kDamping, bool kMassTerm>() __attribute__((always_inline)) {
        run_batch<kDamping, kMassTerm, StepKind::single_step>(b);
      });
}

// The batch loop. Everything it calls in the step loop is inlined.
void run_batch_any(Batch& b) {
  switch (b.kind) {
    case StepKind::composite:
      return run_composite_batch(b);
    case StepKind::houbolt:
      return run_houbolt_batch(b);
    case StepKind::wilson_theta:
      return run_wilson_theta_batch(b);
    case StepKind::single_step:
      return run_single_step_batch(b);
  }
}

// True when a's off-diagonals are one value each (lower in rows 1..n−1, upper in rows
// 0..n−2), as on a uniform rod: then so are those of any combination of such matrices.
bool uniform_off_diagonals(const Tridiagonal& a) {
  const Eigen::Index n = a.size();
  for (Eigen::Index i = 1; i < n; ++i) {
    if (a.lower[i] != a.lower[1] || a.upper[i - 1] != a.upper[0]) return false;
  }
  return true;
}

// The weights of each lane's effective matrix (1 − α_m)·M + (1 − α_f)·b1·Δt²·K [+ (1 − α_f)·
// g1·Δt·C].
struct EffectiveWeights {
  Lanes mass, stiffness, damping;
};

// Every `factored` lane's effective matrix and its factorisation at once: lane by lane the
// operations of Tridiagonal::combined and TridiagonalFactorization::factor, as
// ImplicitIntegrator::initialize does them, so the inverse pivots are the same bits; the
// serial divides of 16 factorisations become those of one. Sets the factorisation's
// coefficients k and the inverse pivots; a lane whose matrix is singular, or every lane when the
// rod is not uniform, is marked failed, taken out of `factored` and does not run. (A composite
// scheme's lanes are factored twice, once per sub-step: into b.first, b.mid.inverse_pivot, then
// into b.coefficients, b.arrays.inverse_pivot.)
void factor_lanes(const SecondOrderSystem& system, std::span<const MethodParams> methods,
                  const EffectiveWeights& w, LaneMask& factored, bool uniform_interior,
                  LaneCoefficients& k, Lanes* inverse_pivot, Batch& b) {
  const Tridiagonal& M = system.mass;
  const Tridiagonal& K = system.stiffness;
  const Tridiagonal& C = system.damping;
  const bool damping = system.has_damping();
  const Eigen::Index n = system.size();
  // Row i of mass.combined(w.mass, stiffness, w.stiffness)[.combined(1, damping, w.damping)].
  const auto effective = [&](const Eigen::VectorXd& m, const Eigen::VectorXd& k,
                             const Eigen::VectorXd& c, Eigen::Index i) {
    Lanes e = w.mass * splat(m[i]) + w.stiffness * splat(k[i]);
    if (damping) e = e + w.damping * splat(c[i]);  // combined(1.0, …): 1·e is e
    return e;
  };
  // The kernel takes one lower and one upper value per lane: checked, not assumed.
  const bool uniform = uniform_interior && uniform_off_diagonals(M) && uniform_off_diagonals(K) &&
                       (!damping || uniform_off_diagonals(C));
  const Lanes lower = effective(M.lower, K.lower, C.lower, 1);
  const Lanes upper = effective(M.upper, K.upper, C.upper, 0);
  std::array<bool, kLanes> singular{};
  Lanes ratio{};
  for (Eigen::Index i = 0; i < n; ++i) {
    Lanes pivot = effective(M.diag, K.diag, C.diag, i);
    pivot = i > 0 ? pivot - lower * ratio : pivot - Lanes{};
    const Lanes inverse = splat(1.0) / pivot;
    for (int l = 0; l < kLanes; ++l) {
      singular[l] = singular[l] || pivot[l] == 0.0 || !std::isfinite(pivot[l]);
    }
    store(&inverse_pivot[i], select(factored, inverse, Lanes{}));
    ratio = i + 1 < n ? upper * inverse : Lanes{};
  }
  k.lower = lower;
  k.upper = upper;
  for (int l = 0; l < kLanes; ++l) {
    if (!factored[l]) continue;
    LaneRun& run = b.lanes[static_cast<std::size_t>(l)];
    if (singular[l] || !uniform) {
      run.summary->status = RunStatus::failed;
      run.summary->message =
          !uniform ? "batched kernel: the mass, the stiffness or the damping is not uniform "
                     "along the rod"
                   : std::string(to_string(kind_of(methods[static_cast<std::size_t>(l)]))) +
                         ": singular effective matrix";
      run = LaneRun{};
      factored.set(l, false);
      for (Eigen::Index i = 0; i < n; ++i) inverse_pivot[i].set(l, 0.0);
      continue;
    }
    // The first row from which the pivots of rows up to n − 2 are one value, bit for bit.
    Eigen::Index converged = n - 1;
    while (converged > 1 && inverse_pivot[converged - 1][l] == inverse_pivot[n - 2][l]) {
      --converged;
    }
    const double tail_pivot = n > 2 ? inverse_pivot[n - 2][l] : 0.0;
    const double tail_ratio = upper[l] * tail_pivot;
    k.tail_pivot.set(l, tail_pivot);
    k.tail_ratio.set(l, tail_ratio);
    k.tail_lower_ratio.set(l, lower[l] * tail_pivot);
    k.tail_ratio2.set(l, tail_ratio * tail_ratio);
    k.tail_begin = std::max(k.tail_begin, converged);
  }
}

// Lane l's constants of a step of the ImplicitCoefficients family over dt, and the weights of
// its effective matrix, by ImplicitIntegrator::initialize's and ::predict's expressions.
void set_lane_coefficients(int l, const ImplicitCoefficients& co, double dt, double gap,
                           LaneCoefficients& k, EffectiveWeights& w) {
  w.mass.set(l, 1.0 - co.alpha_m);
  w.stiffness.set(l, (1.0 - co.alpha_f) * co.b1 * dt * dt);
  w.damping.set(l, (1.0 - co.alpha_f) * co.g1 * dt);
  const double dt2 = dt * dt;
  k.lane_dt.set(l, dt);
  k.dt2_b0.set(l, dt2 * co.b0);
  k.dt_g0.set(l, dt * co.g0);
  k.af.set(l, co.alpha_f);
  k.b1_dt2.set(l, co.b1 * dt2);
  k.g1_dt.set(l, co.g1 * dt);
  k.minus_am.set(l, -co.alpha_m);
  k.mass_term.set(l, co.alpha_m != 0.0);
  k.one_minus_w.set(l, 1.0 - co.contact_weight);
  k.w.set(l, co.contact_weight);
  k.gap.set(l, gap);
}

}  // namespace

namespace {

// One sub-batch (at most kLanes runs) of the implicit kinds of step.
void simulate_implicit_sub_batch(std::span<const RodScene> scenes,
                                 std::span<const MethodParams> methods, const RunOptions& options,
                                 std::vector<LaneBlock>& blocks, LaneSpan<State> starts,
                                 LaneSpan<ContactTrace> traces, std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  const SecondOrderSystem system = assemble_rod(scenes[0]);  // gap aside, every lane's
  const Eigen::Index n = system.size();
  const LaneLoop loop = loop_settings(scenes[0], options);
  const double dt = loop.dt;

  // The interleaved arrays: state, inverse pivots; for a composite scheme also the sub-step's
  // state and its factorisation's inverse pivots, for Wilson-θ the extended step's.
  const StepKind kind = step_kind(methods[0]);
  const bool composite = kind == StepKind::composite;
  const bool houbolt = kind == StepKind::houbolt;
  // A second state and factorisation (Houbolt: its three factorisations and past displacements).
  const bool two_steps = kind == StepKind::composite || kind == StepKind::wilson_theta;
  const int arrays = two_steps ? 8 : houbolt ? 10 : 4;
  LaneStorage storage(blocks, arrays, n);
  Batch b{};
  LaneArrays& x = b.arrays;
  x.n = n;
  x.stiffness = &system.stiffness;
  x.damping = system.has_damping() ? &system.damping : nullptr;
  x.mass = &system.mass;
  const Tridiagonal& K = system.stiffness;
  x.k_lower = n > 2 ? K.lower[1] : 0.0;
  x.k_diag = n > 2 ? K.diag[1] : 0.0;
  x.k_upper = n > 2 ? K.upper[1] : 0.0;
  bool uniform_interior = true;
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    uniform_interior = uniform_interior && K.lower[i] == x.k_lower && K.diag[i] == x.k_diag &&
                       K.upper[i] == x.k_upper;
  }
  uniform_interior = uniform_interior && x.k_lower == x.k_upper;  // symmetric: step_lanes
  const Tridiagonal& M = system.mass;
  x.m_lower = n > 2 ? M.lower[1] : 0.0;
  x.m_diag = n > 2 ? M.diag[1] : 0.0;
  x.m_upper = n > 2 ? M.upper[1] : 0.0;
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    uniform_interior = uniform_interior && M.lower[i] == x.m_lower && M.diag[i] == x.m_diag &&
                       M.upper[i] == x.m_upper;
  }
  storage.take({&x.u, &x.v, &x.a, &x.inverse_pivot});
  b.kind = kind;
  if (two_steps) {
    b.mid = x;
    storage.take({&b.mid.u, &b.mid.v, &b.mid.a, &b.mid.inverse_pivot});
  }
  b.start = starts.data();
  b.loop = loop;
  LaneCoefficients& k = b.coefficients;
  k.gap = splat(kInf);  // unused lanes never touch a wall
  k.dt = dt;
  k.tail_begin = 1;  // raised to where the slowest lane's pivots have converged
  LaneCoefficients& first = b.first;
  first.gap = splat(kInf);
  first.dt = dt;  // unused: the first sub-step reads lane_dt
  first.tail_begin = 1;
  HouboltLanes& h = b.houbolt;
  std::array<EffectiveWeights, 3> houbolt_weights{};
  if (houbolt) {
    for (std::size_t p = 0; p < 3; ++p) {
      h.steps[p].gap = splat(kInf);
      h.steps[p].dt = dt;
      h.steps[p].tail_begin = 1;
      h.pivots[p] = storage.take();
    }
    storage.take({&h.back1, &h.back2, &h.start_velocity});
  }
  const HouboltCoefficients houbolt_steps = houbolt_coefficients();

  EffectiveWeights weights{}, first_weights{};
  LaneMask factored{};  // the lanes whose effective matrix is to be factored
  for (int l = 0; l < count; ++l) {
    const RodScene& scene = scenes[static_cast<std::size_t>(l)];
    const MethodParams& method = methods[static_cast<std::size_t>(l)];
    // same_batch: one kind of step per batch.
    assert(step_kind(method) == kind);
    LaneRun& run = b.lanes[static_cast<std::size_t>(l)];
    if (!prepare_lane(system, scenes, l, options, dt, summaries, traces, starts, run)) {
      continue;
    }

    // The weights of the lane's effective matrix, as ImplicitIntegrator::initialize; the
    // matrix and its factorisation follow for every lane at once, below. A composite scheme:
    // BatheComposite::initialize's two integrators, the first over γ·Δt.
    if (composite) {
      const CompositeCoefficients cc = composite_coefficients(method);
      set_lane_coefficients(l, cc.first, cc.gamma * dt, scene.gap, first, first_weights);
      set_lane_coefficients(l, cc.second, dt, scene.gap, k, weights);
      b.weights.q0.set(l, cc.q0);
      b.weights.q1.set(l, cc.q1);
      b.weights.q2_minus_1_dt.set(l, (cc.q2 - 1.0) * dt);
    } else if (kind == StepKind::wilson_theta) {
      // WilsonTheta::initialize's extended step over θ·Δt; the sample's step Δt and the wall's
      // gap in k (the extended step's gap is set at every step); set_gap_offsets' constants.
      const auto wc = std::get<WilsonThetaCoefficients>(stepper_coefficients(method));
      const double theta = wc.theta, tau = theta * dt;
      set_lane_coefficients(l, wc.extended, tau, scene.gap, first, first_weights);
      k.gap.set(l, scene.gap);
      b.wilson.inverse_theta.set(l, 1.0 / theta);
      b.wilson.theta3.set(l, theta * theta * theta);
      b.wilson.q_weight.set(l, tau * tau / 3.0);
      b.wilson.p_weight.set(l, dt * dt * (3.0 - 1.0 / theta) / 6.0);
    } else if (houbolt) {  // Houbolt::initialize's three integrators, all over Δt
      set_lane_coefficients(l, houbolt_steps.first, dt, scene.gap, h.steps[0], houbolt_weights[0]);
      set_lane_coefficients(l, houbolt_steps.second, dt, scene.gap, h.steps[1], houbolt_weights[1]);
      set_lane_coefficients(l, houbolt_steps.steady, dt, scene.gap, h.steps[2], houbolt_weights[2]);
    } else {
      set_lane_coefficients(l, implicit_coefficients(method), dt, scene.gap, k, weights);
    }
    factored.set(l, true);
  }
  if (two_steps) {
    factor_lanes(system, methods, first_weights, factored, uniform_interior, first,
                 b.mid.inverse_pivot, b);
  }
  if (houbolt) {
    // Each lane starts with the first step's coefficients (run_batch); lanes not stepping hold
    // Houbolt's. The tail rows are those where all three factorisations have converged.
    Eigen::Index tail = 1;
    for (std::size_t p = 0; p < 3; ++p) {
      factor_lanes(system, methods, houbolt_weights[p], factored, uniform_interior, h.steps[p],
                   h.pivots[p], b);
      tail = std::max(tail, h.steps[p].tail_begin);
    }
    for (LaneCoefficients& s : h.steps) s.tail_begin = tail;
    k = h.steps[2];
    std::copy_n(h.pivots[2], n, x.inverse_pivot);
  } else if (kind != StepKind::wilson_theta) {  // Wilson-θ: one factorisation, the extended step's
    factor_lanes(system, methods, weights, factored, uniform_interior, k, x.inverse_pivot, b);
  }
  run_batch_any(b);
  finish_lanes(count, start, traces, summaries);
}

}  // namespace

void simulate_rod_lanes(std::span<const RodScene> scenes, std::span<const MethodParams> methods,
                        const RunOptions& options, BatchStorage ws,
                        std::span<RunSummary> summaries) {
  if (explicit_batch_kind(methods[0]) != ExplicitBatchKind::none) {
    simulate_explicit_lanes(scenes, methods, options, ws, summaries);
    return;
  }
  if (stepped_by<KrAlphaCoefficients>(methods[0])) {
    simulate_kr_alpha_lanes(scenes, methods, options, ws, summaries);
    return;
  }
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    simulate_implicit_sub_batch(scenes.subspan(first, count), methods.subspan(first, count),
                                options, ws.blocks, sub_batch_part(ws.starts, first),
                                sub_batch_part(ws.traces, first), summaries.subspan(first, count));
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
