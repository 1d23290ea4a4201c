#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_model.hpp"
#include "core/batch/sparse_lanes.hpp"
#include "core/contact/contact_treatment.hpp"
#include "core/methods/central_difference_recurrence.hpp"

// Last: the level's target for the rest of the file (core/batch/kernel_target.hpp), then the
// lane vocabulary (kept in this order: clang-format would sort them).
// clang-format off
#include "core/batch/kernel_target.hpp"
#include "core/batch/simd_lanes.hpp"
// clang-format on

namespace impactid::IMPACTID_KERNEL_NAMESPACE {

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

namespace {

// y += s·A·x for every lane, `kParts` Lanes per unknown: multiply_add's column-major walk
// (core/model/sparse_system.cpp) with its skip of a zero s·x_j as a blend.
template <int kParts>
[[gnu::always_inline]] inline void product_add(const SparseMatrix& a, double s, const Lanes* x,
                                               Lanes* y) {
  const double* values = a.valuePtr();
  const int* rows = a.innerIndexPtr();
  const int* starts = a.outerIndexPtr();
  const int* counts = a.innerNonZeroPtr();  // null when compressed
  const Lanes scale = splat(s);
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    Lanes sx[kParts];
    LaneMask on[kParts];
    bool any = false;
    for (int p = 0; p < kParts; ++p) {
      sx[p] = scale * x[j * kParts + p];
      on[p] = nonzero(sx[p]);
      any = any || any_lane(on[p]);
    }
    if (!any) continue;  // every lane skips the column, as the scalar product does
    const int begin = starts[j];
    const int end = counts ? begin + counts[j] : starts[j + 1];
    for (int e = begin; e < end; ++e) {
      const Lanes value = splat(values[e]);
      Lanes* row = y + static_cast<Eigen::Index>(rows[e]) * kParts;
      for (int p = 0; p < kParts; ++p) {
        store(&row[p], select(on[p], row[p] + value * sx[p], row[p]));
      }
    }
  }
}

// quadratic_form(a, x) of every lane (core/model/sparse_system.cpp): Σ_j x_j·(Σ_i a_ij·x_i), in
// the scalar's order.
Lanes quadratic_forms(const SparseMatrix& a, const Lanes* x) {
  const double* values = a.valuePtr();
  const int* rows = a.innerIndexPtr();
  const int* starts = a.outerIndexPtr();
  const int* counts = a.innerNonZeroPtr();
  Lanes sum = splat(0.0);
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    Lanes column = splat(0.0);
    const int begin = starts[j];
    const int end = counts ? begin + counts[j] : starts[j + 1];
    for (int e = begin; e < end; ++e) column = column + splat(values[e]) * x[rows[e]];
    sum = sum + x[j] * column;
  }
  return sum;
}

// a == b lane by lane.
[[gnu::always_inline]] inline LaneMask equal(const Lanes& a, const Lanes& b) {
  LaneMask out;
  for_each_register([&](auto k) __attribute__((always_inline)) { out.r[k] = a.r[k] == b.r[k]; });
  return out;
}

// One constraint of the model: its DOFs and probe (every lane's), and each lane's Delassus
// diagonal entry d = (G·A⁻¹·Gᵀ)_jj with its square root (solve_diagonal_contact_lcp's).
struct alignas(LaneBlock) LaneConstraint {
  Eigen::Index plus, minus, velocity_dof;
  Lanes gap, area, d, root_d;
};

struct alignas(LaneBlock) ModelBatch {
  const SparseSystem* system;
  Eigen::Index n;
  int m;
  Lanes *u_previous, *u, *u_next, *scratch, *inverse_diagonal;
  std::vector<LaneConstraint> constraints;
  Lanes dt, inv_dt2, two_dt;
  std::array<LaneRun, kLanes> lanes;
  std::array<int, kLanes> primary;
  std::array<double, kLanes> step;  // each lane's Δt, for its energy
  Lanes t;                          // each lane's recurrence time (that of u)
  Lanes penetration;                // each lane's largest violation (RunSummary::max_penetration)
  Lanes* chunk;                     // kTraceChunk samples × (m pressures, m velocities)
  int energy_check_interval;
  double energy_growth_limit;
  bool fused;  // predict_fused applies
};

// Samples buffered before they are written into the lanes' traces, as in the other kernels.
constexpr long kChunk = 32;

// Writes the buffered samples [begin, through] into the lanes' traces.
void flush_chunk(ModelBatch& b, long begin, long through) {
  flush_contact_chunk(b.lanes, b.primary, b.chunk, b.m, begin, through);
}

// The predictor in one pass over the unknowns, when M is stored as its diagonal alone and K is
// exactly symmetric with sorted rows (ModelBatch::fused): the scalar scatters M·s and then K's
// columns into u₊, so u₊[i] receives m_i·s_i first and then K(i, j)·(−u_j) for j increasing; K's
// column i holds the same entries K(j, i) = K(i, j), sorted by j, so gathering it row by row
// adds the same products in the same order (each skipped where −u_j is zero, as the scatter
// skips the column), and each row is read and written once instead of four times.
void predict_fused(ModelBatch& b) {
  const Eigen::Index n = b.n;
  const SparseMatrix& k = b.system->stiffness;
  const double* mass = b.system->mass.valuePtr();  // one entry per column, its diagonal
  const double* values = k.valuePtr();
  const int* rows = k.innerIndexPtr();
  const int* starts = k.outerIndexPtr();
  const Lanes* up = b.u_previous;
  const Lanes* u = b.u;
  Lanes* un = b.u_next;
  const Lanes inv_dt2 = b.inv_dt2, two = splat(2.0), zero = splat(0.0), minus_one = splat(-1.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Lanes s = (two * u[i] - up[i]) * inv_dt2;
    Lanes sum = select(nonzero(s), zero + splat(mass[i]) * s, zero);
    for (int e = starts[i]; e < starts[i + 1]; ++e) {
      const Lanes sx = minus_one * u[rows[e]];
      sum = select(nonzero(sx), sum + splat(values[e]) * sx, sum);
    }
    store(&un[i], sum * b.inverse_diagonal[i]);
  }
}

// SparseCentralDifference::step in every lane, up to its finish(): the contact-free u₊, the
// contacts' forces by the diagonal Delassus matrix, the correction and the walls. Leaves each
// constraint's force in `forces`.
void step_model(ModelBatch& b, Lanes* forces) {
  const Eigen::Index n = b.n;
  const SparseSystem& system = *b.system;
  Lanes *up = b.u_previous, *u = b.u, *un = b.u_next, *scratch = b.scratch;
  const Lanes inv_dt2 = b.inv_dt2, two = splat(2.0), zero = splat(0.0);
  // CentralDifferenceRecurrence::predict without damping: M·(2u − u₋)/Δt² − K·u, then the solve.
  if (b.fused) {
    predict_fused(b);
  } else {
    for (Eigen::Index i = 0; i < n; ++i) {
      store(&scratch[i], (two * u[i] - up[i]) * inv_dt2);
      store(&un[i], zero);
    }
    product_add<1>(system.mass, 1.0, scratch, un);
    product_add<1>(system.stiffness, -1.0, u, un);
    for (Eigen::Index i = 0; i < n; ++i) store(&un[i], un[i] * b.inverse_diagonal[i]);
  }

  // The violations at t + Δt, solve_diagonal_contact_lcp's forces (one penetrating constraint:
  // p/d; several: (p/√d)/√d), then the correction A⁻¹·Gᵀ·μ on the constraints' DOFs (each DOF
  // belongs to one constraint when D is diagonal, and subtracting the zeros elsewhere changes no
  // bit) and the walls put on their gap.
  const int m = b.m;
  Lanes count = zero;
  for (int j = 0; j < m; ++j) {
    const LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
    Lanes g = -c.gap;
    if (c.plus >= 0) g = g + un[c.plus];
    if (c.minus >= 0) g = g - un[c.minus];
    forces[j] = g;  // the violation, until the force replaces it below
    count = count + select(greater(g, zero), splat(1.0), zero);
  }
  const LaneMask single = equal(count, splat(1.0));
  for (int j = 0; j < m; ++j) {
    const LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
    const Lanes p = forces[j];
    const LaneMask on = greater(p, zero);
    forces[j] = select(on, select(single, p / c.d, (p / c.root_d) / c.root_d), zero);
  }
  for (int j = 0; j < m; ++j) {
    const LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
    const LaneMask on = greater(forces[j], zero);
    if (!any_lane(on)) continue;
    if (c.plus >= 0) {
      const Lanes correction = (zero + forces[j]) * b.inverse_diagonal[c.plus];
      store(&un[c.plus], select(on, un[c.plus] - correction, un[c.plus]));
    }
    if (c.minus >= 0) {
      const Lanes correction = (zero - forces[j]) * b.inverse_diagonal[c.minus];
      store(&un[c.minus], select(on, un[c.minus] - correction, un[c.minus]));
    }
  }
  for (int j = 0; j < m; ++j) {  // snap_walls
    const LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
    const LaneMask on = greater(forces[j], zero);
    if (c.minus < 0) store(&un[c.plus], select(on, c.gap, un[c.plus]));
    if (c.plus < 0) store(&un[c.minus], select(on, -c.gap, un[c.minus]));
  }
}

// The method's own energy of every lane after the recurrence moved on (u₋ = u_t, u = u_{t+Δt}):
// CentralDifferenceRecurrence::energy, with scratch and u₊ as its scratch.
Lanes model_energy(ModelBatch& b) {
  const Eigen::Index n = b.n;
  const Lanes half = splat(0.5);
  for (Eigen::Index i = 0; i < n; ++i) {
    store(&b.scratch[i], (b.u[i] - b.u_previous[i]) / b.dt);
    store(&b.u_next[i], half * (b.u[i] + b.u_previous[i]));
  }
  const Lanes mass_w = quadratic_forms(b.system->mass, b.scratch);
  const Lanes stiffness_w = quadratic_forms(b.system->stiffness, b.scratch);
  const Lanes stiffness_m = quadratic_forms(b.system->stiffness, b.u_next);
  Lanes out{};
  for (int l = 0; l < kLanes; ++l) {
    out.set(l, central_difference_energy(mass_w[l], stiffness_w[l], stiffness_m[l],
                                         b.step[static_cast<std::size_t>(l)]));
  }
  return out;
}

// run_steps with run_listed_steps' record (core/run/simulation.cpp) for every lane: the samples
// from the first lane's start to the last lane's end, the bookkeeping lane by lane at events only
// (a lane starting, checking its energy or ending, a non-finite value), as the chain kernel does.
void run_model(ModelBatch& b, const std::array<const CentralDifferenceRecurrence*, kLanes>& start) {
  std::array<LaneRun, kLanes>& lanes = b.lanes;
  const int m = b.m;
  const Eigen::Index n = b.n;
  const auto [begin, end] = lane_samples(lanes);
  // Each constraint's force and velocity of the sample (LaneBlocks: aligned for the registers).
  std::vector<LaneBlock> force_blocks(static_cast<std::size_t>(m)), velocity_blocks(force_blocks);
  const std::span<Lanes> forces(reinterpret_cast<Lanes*>(force_blocks.data()), m);
  const std::span<Lanes> velocities(reinterpret_cast<Lanes*>(velocity_blocks.data()), m);
  LaneMask stepping{};
  Lanes penetration = b.penetration;
  long chunk_begin = begin;
  long event = next_lane_event(lanes, begin);
  for (long i = begin; i <= end; ++i) {
    const bool at_event = i == event;
    if (at_event) {
      flush_chunk(b, chunk_begin, i - 1);
      chunk_begin = i;
      for (int l = 0; l < kLanes; ++l) {
        LaneRun& run = lanes[static_cast<std::size_t>(l)];
        if (run.first != i || run.first > run.last) continue;
        const CentralDifferenceRecurrence& r = *start[static_cast<std::size_t>(l)];
        for (Eigen::Index k = 0; k < n; ++k) {
          b.u_previous[k].set(l, r.u_previous[k]);
          b.u[k].set(l, r.u[k]);
        }
        b.t.set(l, r.t);
        run.next_check = run.first - 1 + b.energy_check_interval;
        run.stepping = true;
        stepping.set(l, true);
      }
    }
    step_model(b, forces.data());
    // finish(): the sample at t (u before the move, the central velocity), then u₋ ← u ← u₊.
    const Lanes t = b.t;
    b.t = b.t + b.dt;
    Lanes* sample = b.chunk + 2 * m * (i - chunk_begin);
    bool finite = true;
    for (int k = 0; k < m; ++k) {
      const LaneConstraint& c = b.constraints[static_cast<std::size_t>(k)];
      const Lanes v = (b.u_next[c.velocity_dof] - b.u_previous[c.velocity_dof]) / b.two_dt;
      velocities[static_cast<std::size_t>(k)] = v;
      store(&sample[k], forces[static_cast<std::size_t>(k)] / c.area);
      store(&sample[m + k], v);
      finite = finite && all_finite(forces[static_cast<std::size_t>(k)], v);
      Lanes g = -c.gap;
      if (c.plus >= 0) g = g + b.u[c.plus];
      if (c.minus >= 0) g = g - b.u[c.minus];
      penetration = select(greater(g, penetration) & stepping, g, penetration);
    }
    std::swap(b.u_previous, b.u);
    std::swap(b.u, b.u_next);
    if (!at_event && finite) {
      if (i + 1 - chunk_begin == kChunk) {
        flush_chunk(b, chunk_begin, i);
        chunk_begin = i + 1;
      }
      continue;
    }
    flush_chunk(b, chunk_begin, i);
    chunk_begin = i + 1;

    Lanes energy{};
    if (energy_due(lanes, i)) energy = model_energy(b);
    for (int l = 0; l < kLanes; ++l) {
      LaneRun& run = lanes[static_cast<std::size_t>(l)];
      if (!run.stepping) continue;
      check_lane_energy(run, i, energy[l], t[l], b.energy_check_interval, b.energy_growth_limit);
      if (run.stepping) {
        for (std::size_t k = 0; k < forces.size(); ++k) {
          if (!std::isfinite(forces[k][l]) || !std::isfinite(velocities[k][l])) {
            stop_unstable(run, "non-finite values at t = " + format_value(t[l]) + " s");
            break;
          }
        }
      }
      if (run.stepping && i == run.last) run.stepping = false;
      if (!run.stepping) {  // the lane steps zeros from now on
        for (Eigen::Index k = 0; k < n; ++k) {
          b.u_previous[k].set(l, 0.0);
          b.u[k].set(l, 0.0);
        }
        stepping.set(l, false);
      }
    }
    event = next_lane_event(lanes, i + 1);
    if (event == std::numeric_limits<long>::max()) break;
  }
  b.penetration = penetration;
}

// Whether predict_fused gives the scalar's bits (core/model/sparse_system.hpp says why).
bool fused_predictor(const SparseSystem& system) {
  return stores_diagonal_only(system.mass) && is_exactly_symmetric(system.stiffness);
}

// Whether the kernel takes a lane whose stepper is set up: its step is the one step_model repeats
// (a diagonal left-hand matrix with finite inverses, a diagonal Delassus matrix) and its energy
// the method's own (within the explicit limit).
bool kernel_takes(const SparseCentralDifference& stepper) {
  const SparseFactorization& f = stepper.factorization();
  return f.diagonal() && f.inverse_diagonal().allFinite() &&
         stepper.contact_problem().delassus_diagonal && stepper.within_stability_limit();
}

// One sub-batch (at most kLanes runs).
void simulate_model_sub_batch(std::span<const AssembledScene* const> scenes,
                              std::span<const MethodParams> methods, const RunOptions& options,
                              std::vector<LaneBlock>& storage, LaneSpan<State> states,
                              LaneSpan<SparseCentralDifference> steppers,
                              LaneSpan<ContactTrace> traces, SimulationWorkspace& scalar,
                              int& kernel_total, std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  const SparseSystem& system = *scenes[0]->sparse;  // every lane's
  const Eigen::Index n = system.size();
  const int m = static_cast<int>(system.constraints.size());
  const ContactPenalties contact = resolve_contact(options.contact, system);

  // Each lane's set-up, as simulate() does it: prepare_run, the stepper's initialize() and its
  // first step (the state at the first stepped sample). A lane the kernel does not take runs
  // through simulate() instead.
  std::array<const CentralDifferenceRecurrence*, kLanes> recurrences{};
  LaneMask running{};
  int kernel_lanes = 0;
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    const AssembledScene& scene = *scenes[lane];
    RunSummary& summary = summaries[lane];
    State& state = states[lane];
    if (!prepare_run(scene, options, traces[lane], state, summary)) continue;
    const auto cdm = std::get<CentralDifferenceCoefficients>(stepper_coefficients(methods[lane]));
    SparseCentralDifference& stepper = steppers[lane];
    if (!stepper.initialize(system, cdm.velocity, scene.dt, state, contact)) {
      summary.status = RunStatus::failed;
      summary.message = "central difference: " + stepper.failure();
      continue;
    }
    if (!kernel_takes(stepper)) {
      summary = simulate(scene, methods[lane], options, scalar);
      std::swap(traces[lane], scalar.trace);
      continue;
    }
    summary.stable_dt = stepper.stable_step();
    stepper.step(system, state);
    recurrences[lane] = &stepper.recurrence();
    running.set(l, true);
    ++kernel_lanes;
  }
  kernel_total += kernel_lanes;
  if (kernel_lanes == 0) return;

  ModelBatch b{};
  b.system = &system;
  b.n = n;
  b.m = m;
  storage.assign(static_cast<std::size_t>(5 * n + 2 * m * kChunk), LaneBlock{});
  Lanes* next = reinterpret_cast<Lanes*>(storage.data());
  const auto take = [&](Eigen::Index rows) {
    Lanes* p = next;
    next += rows;
    return p;
  };
  b.u_previous = take(n), b.u = take(n), b.u_next = take(n), b.scratch = take(n);
  b.inverse_diagonal = take(n);
  b.chunk = take(2 * m * kChunk);
  b.dt = splat(1.0), b.inv_dt2 = splat(1.0), b.two_dt = splat(2.0);  // idle lanes: harmless
  b.step.fill(1.0);
  b.constraints.resize(static_cast<std::size_t>(m));
  for (int j = 0; j < m; ++j) {
    const Constraint& constraint = system.constraints[static_cast<std::size_t>(j)];
    const ContactProbe& probe = scenes[0]->probes[static_cast<std::size_t>(j)];
    LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
    c.plus = constraint.plus;
    c.minus = constraint.minus;
    c.velocity_dof = probe.velocity_dof;
    c.gap = splat(constraint.gap);
    c.area = splat(probe.area);
    c.d = c.root_d = splat(1.0);
  }
  b.energy_check_interval = options.energy_check_interval;
  b.energy_growth_limit = options.energy_growth_limit;
  b.fused = fused_predictor(system);
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    if (!running[l]) continue;
    const AssembledScene& scene = *scenes[lane];
    const SparseCentralDifference& stepper = steppers[lane];
    const double dt = stepper.recurrence().dt;
    b.dt.set(l, dt);
    b.inv_dt2.set(l, 1.0 / (dt * dt));
    b.two_dt.set(l, 2.0 * dt);
    b.step[lane] = dt;
    const Eigen::VectorXd& inverse = stepper.factorization().inverse_diagonal();
    for (Eigen::Index i = 0; i < n; ++i) b.inverse_diagonal[i].set(l, inverse[i]);
    const Eigen::MatrixXd& d = stepper.contact_problem().delassus;
    for (int j = 0; j < m; ++j) {
      LaneConstraint& c = b.constraints[static_cast<std::size_t>(j)];
      c.d.set(l, d(j, j));
      c.root_d.set(l, std::sqrt(d(j, j)));
    }
    b.primary[lane] = scene.primary;
    b.penetration.set(l, summaries[lane].max_penetration);
    LaneRun& run = b.lanes[lane];
    run.summary = &summaries[lane];
    run.trace = &traces[lane];
    run.first = summaries[lane].skipped_steps;
    run.last = scene.step_count - 1;
    run.energy_bound = options.energy_growth_limit * summaries[lane].initial_energy;
  }
  run_model(b, recurrences);

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    if (!running[l]) continue;
    summaries[lane].max_penetration = b.penetration[l];
    summaries[lane].wall_time_s = seconds / kernel_lanes;
  }
}

}  // namespace

void multiply_add_lanes(const SparseMatrix& a, double s, std::span<const LaneBlock> x,
                        std::span<LaneBlock> y) {
  // A LaneBlock is kBatchLanes doubles, a Lanes kLanes (8 on x86-64-v3, whose 16 registers would
  // spill 16 lanes in the step kernels): a block is kBatchLanes / kLanes Lanes, all walked per
  // stored entry.
  product_add<kBatchLanes / kLanes>(a, s, reinterpret_cast<const Lanes*>(x.data()),
                                    reinterpret_cast<Lanes*>(y.data()));
}

void simulate_model_lanes(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          std::vector<LaneBlock>& storage, std::array<State, kBatchLanes>& states,
                          std::array<SparseCentralDifference, kBatchLanes>& steppers,
                          std::array<ContactTrace, kBatchLanes>& traces,
                          SimulationWorkspace& scalar, int& kernel_lanes,
                          std::span<RunSummary> summaries) {
  kernel_lanes = 0;
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    simulate_model_sub_batch(scenes.subspan(first, count), methods.subspan(first, count), options,
                             storage, sub_batch_part(states, first),
                             sub_batch_part(steppers, first), sub_batch_part(traces, first),
                             scalar, kernel_lanes, summaries.subspan(first, count));
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
