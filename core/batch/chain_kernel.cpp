#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/algebra/contact_lcp.hpp"
#include "core/algebra/tridiagonal.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_chain.hpp"

// Last: the level's target for the rest of the file (core/batch/kernel_target.hpp), then the lane
// vocabulary and this kernel's parts (chain_step.hpp: headers of this file alone, so that the
// kernel stays one translation unit), compiled for the level (kept in this order: clang-format
// would sort them).
// clang-format off
#include "core/batch/kernel_target.hpp"
#include "core/batch/simd_lanes.hpp"
#include "core/batch/chain_step.hpp"
// clang-format on

namespace impactid::IMPACTID_KERNEL_NAMESPACE {
namespace {

using namespace simd;  // NOLINT(google-build-using-namespace): the kernel's vocabulary

constexpr long kTraceChunk = 32;

struct alignas(LaneBlock) ChainBatch {
  ChainArrays arrays;
  ChainCoefficients coefficients;
  std::array<LaneRun, kLanes> lanes;
  State* start = nullptr;
  Lanes* chunk;                     // kTraceChunk samples × (m pressures, m velocities)
  std::array<int, kLanes> primary;  // each lane's primary contact (its trace's main columns)
  int energy_check_interval;
  double energy_growth_limit;
  Lanes penetration;  // each lane's largest violation so far (RunSummary::max_penetration)
};

// Writes the buffered samples [begin, through] into the lanes' traces.
void flush_chunk(ChainBatch& b, long begin, long through) {
  flush_contact_chunk(b.lanes, b.primary, b.chunk, b.arrays.m, begin, through);
}

// The samples from the first lane's start to the last lane's end, with run_steps' bookkeeping
// (core/run/simulation.cpp) lane by lane at events only, as in the rod's kernel (run_batch).
template <bool kDamping, bool kMassTerm>
[[gnu::always_inline]] inline void run_chain(ChainBatch& b) {
  const ChainArrays& x = b.arrays;
  ChainCoefficients c = b.coefficients;
  std::array<LaneRun, kLanes>& lanes = b.lanes;
  const int m = x.m;
  const auto [begin, end] = lane_samples(lanes);
  std::array<Lanes, kMaxConstraints> multipliers{};
  PendingCorrections pending;
  LaneMask stepping{};
  Lanes penetration = b.penetration, t{};
  long chunk_begin = begin;
  long event = next_lane_event(lanes, begin);
  for (long i = begin; i <= end; ++i) {
    const bool at_event = i == event;
    bool starting = false;
    if (at_event) {
      flush_chunk(b, chunk_begin, i - 1);
      chunk_begin = i;
      for (int l = 0; l < kLanes; ++l) {
        LaneRun& run = lanes[static_cast<std::size_t>(l)];
        if (run.first != i || run.first > run.last) continue;
        const State& start = b.start[static_cast<std::size_t>(l)];
        set_lane_state(x.u, x.v, x.a, x.n, l, &start);
        c.plain_state.set(l, true);
        starting = true;
        for (int k = 0; k < m; ++k) multipliers[k].set(l, start.multipliers[k]);
        t.set(l, start.t);
        run.next_check = run.first - 1 + b.energy_check_interval;
        run.stepping = true;
        stepping.set(l, true);
      }
    }
    if (starting) {
      step_chain<kDamping, kMassTerm, true, true>(x, c, multipliers.data(), pending);
      c.plain_state = LaneMask{};
    } else if (pending.count > 0) {
      step_chain<kDamping, kMassTerm, false, true>(x, c, multipliers.data(), pending);
    } else {
      step_chain<kDamping, kMassTerm, false, false>(x, c, multipliers.data(), pending);
    }
    t = t + splat(c.dt);

    // The samples of every contact, and the largest violation (run_listed_steps' record).
    Lanes* sample = b.chunk + 2 * m * (i - chunk_begin);
    bool finite = true;
    for (int k = 0; k < m; ++k) {
      const LaneContact& contact = x.contacts[k];
      const Lanes v = velocity(x, c, pending, contact.velocity_dof);
      store(&sample[k], multipliers[k] / contact.area);
      store(&sample[m + k], v);
      finite = finite && all_finite(multipliers[k], v);
      Lanes g = -contact.gap;
      if (contact.plus >= 0) g = g + displacement(x, c, pending, contact.plus);
      if (contact.minus >= 0) g = g - displacement(x, c, pending, contact.minus);
      const LaneMask larger = greater(g, penetration);  // std::max(penetration, g)
      penetration = select(larger & stepping, g, penetration);
    }
    if (!at_event && finite) {
      if (i + 1 - chunk_begin == kTraceChunk) {
        flush_chunk(b, chunk_begin, i);
        chunk_begin = i + 1;
      }
      continue;
    }
    flush_chunk(b, chunk_begin, i);
    chunk_begin = i + 1;

    Lanes energy{};
    if (energy_due(lanes, i)) energy = chain_energy(x, c, pending);
    for (int l = 0; l < kLanes; ++l) {
      LaneRun& run = lanes[static_cast<std::size_t>(l)];
      if (!run.stepping) continue;
      check_lane_energy(run, i, energy[l], t[l], b.energy_check_interval, b.energy_growth_limit);
      if (run.stepping) {
        for (int k = 0; k < m; ++k) {
          if (!std::isfinite(multipliers[k][l]) ||
              !std::isfinite(velocity(x, c, pending, x.contacts[k].velocity_dof)[l])) {
            stop_unstable(run, "non-finite values at t = " + format_value(t[l]) + " s");
            break;
          }
        }
      }
      if (run.stepping && i == run.last) run.stepping = false;
      if (!run.stepping) {
        set_lane_state(x.u, x.v, x.a, x.n, l, nullptr);
        for (int k = 0; k < m; ++k) multipliers[k].set(l, 0.0);
        for (int q = 0; q < pending.count; ++q) {  // its state stays zero
          pending.force[q].set(l, 0.0);
          pending.on[q].set(l, false);
        }
        stepping.set(l, false);
      }
    }
    event = next_lane_event(lanes, i + 1);
    if (event == std::numeric_limits<long>::max()) break;
  }
  b.penetration = penetration;
}

void run_chain_any(ChainBatch& b) {
  with_kernel_flags(
      b.arrays.damping != nullptr, any_lane(b.coefficients.mass_term),
      [&b]<bool kDamping, bool kMassTerm>()
          __attribute__((always_inline)) { run_chain<kDamping, kMassTerm>(b); });
}

// The blocks of rows 1 .. n − 3 (RowBlock), from the factors of every lane: uniform runs of at
// least kMinUniformRows rows, the forced rows alone, generic runs between them.
constexpr Eigen::Index kMinUniformRows = 8;
std::vector<RowBlock> row_blocks(const ChainArrays& x, const std::vector<ForceRow>& force_rows) {
  const Eigen::Index last = x.n - 1;
  const Tridiagonal& K = *x.stiffness;
  const auto forced = [&](Eigen::Index i) {
    return std::any_of(force_rows.begin(), force_rows.end(),
                       [i](const ForceRow& f) { return f.row == i; });
  };
  const auto same_bits = [](const void* a, const void* b, std::size_t size) {
    return std::memcmp(a, b, size) == 0;
  };
  // Row i's K and factors equal row j's, bit for bit.
  const auto same_row = [&](Eigen::Index i, Eigen::Index j) {
    return same_bits(&K.lower[i], &K.lower[j], sizeof(double)) &&
           same_bits(&K.diag[i], &K.diag[j], sizeof(double)) &&
           same_bits(&K.upper[i], &K.upper[j], sizeof(double)) &&
           same_bits(&x.minus_inverse_pivot[i], &x.minus_inverse_pivot[j], sizeof(Lanes)) &&
           same_bits(&x.minus_lower_ratio[i], &x.minus_lower_ratio[j], sizeof(Lanes)) &&
           same_bits(&x.minus_upper_ratio[i], &x.minus_upper_ratio[j], sizeof(Lanes));
  };
  std::vector<RowBlock> blocks;
  const auto add_generic = [&](Eigen::Index begin, Eigen::Index end) {
    if (begin == end) return;
    if (!blocks.empty() && !blocks.back().forces && !blocks.back().uniform &&
        blocks.back().end == begin) {
      blocks.back().end = end;
      return;
    }
    RowBlock block;
    block.begin = begin;
    block.end = end;
    blocks.push_back(block);
  };
  for (Eigen::Index i = 1; i < last - 1;) {
    if (forced(i)) {
      RowBlock block;
      block.begin = i;
      block.end = i + 1;
      block.forces = true;
      blocks.push_back(block);
      ++i;
      continue;
    }
    Eigen::Index j = i + 1;
    while (j < last - 1 && !forced(j) && same_row(j, i)) ++j;
    if (j - i < kMinUniformRows) {
      add_generic(i, j);
    } else {
      RowBlock block;
      block.begin = i;
      block.end = j;
      block.uniform = true;
      block.k_lower = K.lower[i];
      block.k_diag = K.diag[i];
      block.k_upper = K.upper[i];
      block.minus_inverse_pivot = x.minus_inverse_pivot[i];
      block.minus_lower_ratio = x.minus_lower_ratio[i];
      block.minus_upper_ratio = x.minus_upper_ratio[i];
      blocks.push_back(block);
    }
    i = j;
  }
  return blocks;
}

}  // namespace

namespace {

// One sub-batch (at most kLanes runs) of the chain kernel.
void simulate_chain_sub_batch(std::span<const AssembledScene* const> scenes,
                              std::span<const MethodParams> methods, const RunOptions& options,
                              std::vector<LaneBlock>& storage, LaneSpan<State> starts,
                              LaneSpan<ImplicitIntegrator> integrators,
                              LaneSpan<ContactTrace> traces, std::span<RunSummary> summaries) {
  const auto start = std::chrono::steady_clock::now();
  const int count = static_cast<int>(scenes.size());
  const SecondOrderSystem& system = scenes[0]->system;  // every lane's, gaps aside
  const Eigen::Index n = system.size();
  const int m = static_cast<int>(system.constraints.size());
  const double dt = scenes[0]->dt;

  // Each lane's start (simulate()'s set-up) and its integrator's set-up.
  ChainBatch b{};
  LaneMask running{};
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    const AssembledScene& scene = *scenes[lane];
    RunSummary& summary = summaries[lane];
    if (!prepare_run(scene, options, traces[lane], starts[lane], summary)) continue;
    if (!integrators[lane].initialize(system, implicit_coefficients(methods[lane]), dt)) {
      summary.status = RunStatus::failed;
      summary.message =
          std::string(to_string(kind_of(methods[lane]))) + ": singular effective matrix";
      continue;
    }
    running.set(l, true);
  }

  // The contacts' rows: the union and the intersection over the running lanes.
  std::vector<LaneContact> contacts(static_cast<std::size_t>(m));
  Eigen::Index column_rows = 0;
  for (int j = 0; j < m; ++j) {
    LaneContact& k = contacts[static_cast<std::size_t>(j)];
    const Constraint& constraint = system.constraints[static_cast<std::size_t>(j)];
    const ContactProbe& probe = scenes[0]->probes[static_cast<std::size_t>(j)];
    k.plus = constraint.plus;
    k.minus = constraint.minus;
    k.area = splat(probe.area);
    k.velocity_dof = probe.velocity_dof;
    k.gap = splat(kInf);  // idle lanes never touch a contact
    k.begin = k.common_begin = n;
    k.end = k.common_end = 0;
    for (int l = 0; l < count; ++l) {
      if (!running[l]) continue;
      const auto [first, end] =
          integrators[static_cast<std::size_t>(l)].constraint_rows()[static_cast<std::size_t>(j)];
      k.lane_begin[static_cast<std::size_t>(l)] = first;
      k.lane_end[static_cast<std::size_t>(l)] = end;
      k.begin = std::min(k.begin, first);
      k.end = std::max(k.end, end);
      k.gap.set(
          l,
          scenes[static_cast<std::size_t>(l)]->system.constraints[static_cast<std::size_t>(j)].gap);
    }
    Eigen::Index common_begin = 0, common_end = n;
    for (int l = 0; l < count; ++l) {
      if (!running[l]) continue;
      common_begin = std::max(common_begin, k.lane_begin[static_cast<std::size_t>(l)]);
      common_end = std::min(common_end, k.lane_end[static_cast<std::size_t>(l)]);
    }
    if (k.begin >= k.end) k.begin = k.end = 0;  // no running lane
    k.common_begin = std::clamp(common_begin, k.begin, k.end);
    k.common_end = std::clamp(common_end, k.common_begin, k.end);
    column_rows += k.end - k.begin;
  }

  // The interleaved arrays: state, factorisation, columns, trace buffer.
  storage.assign(static_cast<std::size_t>(6 * n + column_rows + 2 * m * kTraceChunk), LaneBlock{});
  Lanes* block = reinterpret_cast<Lanes*>(storage.data());
  const auto take = [&](Eigen::Index rows) {
    Lanes* p = block;
    block += rows;
    return p;
  };
  ChainArrays& x = b.arrays;
  x.n = n;
  x.stiffness = &system.stiffness;
  x.damping = system.has_damping() ? &system.damping : nullptr;
  x.mass = &system.mass;
  x.u = take(n), x.v = take(n), x.a = take(n);
  x.minus_inverse_pivot = take(n), x.minus_lower_ratio = take(n), x.minus_upper_ratio = take(n);
  for (LaneContact& k : contacts) k.influence = take(k.end - k.begin);
  b.chunk = take(2 * m * kTraceChunk);
  x.m = m;
  x.contacts = contacts.data();
  std::vector<ForceRow> force_rows;
  for (int j = 0; j < m; ++j) {
    const Constraint& constraint = system.constraints[static_cast<std::size_t>(j)];
    if (constraint.plus >= 0) force_rows.push_back({constraint.plus, j, true});
    if (constraint.minus >= 0) force_rows.push_back({constraint.minus, j, false});
  }
  std::stable_sort(force_rows.begin(), force_rows.end(),
                   [](const ForceRow& p, const ForceRow& q) { return p.row < q.row; });
  x.force_rows = force_rows.data();
  x.force_row_count = static_cast<int>(force_rows.size());

  ChainCoefficients& k = b.coefficients;
  k.dt = dt;
  k.w = splat(1.0);  // idle lanes: λ = 0/1
  b.start = starts.data();
  b.energy_check_interval = options.energy_check_interval;
  b.energy_growth_limit = options.energy_growth_limit;
  for (int l = 0; l < count; ++l) {
    const auto lane = static_cast<std::size_t>(l);
    b.penetration.set(l, summaries[lane].max_penetration);
    if (!running[l]) continue;
    const ImplicitIntegrator& integrator = integrators[lane];
    const TridiagonalFactorization& f = integrator.factorization();
    for (Eigen::Index i = 0; i < n; ++i) {
      x.minus_inverse_pivot[i].set(l, -f.inverse_pivots()[i]);
      x.minus_lower_ratio[i].set(l, -f.lower_ratios()[i]);
      x.minus_upper_ratio[i].set(l, -f.upper_ratios()[i]);
    }
    for (int j = 0; j < m; ++j) {
      LaneContact& contact = contacts[static_cast<std::size_t>(j)];
      for (Eigen::Index i = contact.lane_begin[lane]; i < contact.lane_end[lane]; ++i) {
        contact.influence[i - contact.begin].set(l, integrator.constraint_influence()(i, j));
      }
    }
    x.delassus[lane] = integrator.delassus().data();
    if (m == 1) x.single_delassus.set(l, integrator.delassus()(0, 0));

    const ImplicitCoefficients co = implicit_coefficients(methods[lane]);
    const double dt2 = dt * dt;
    k.dt2_b0.set(l, dt2 * co.b0);
    k.dt_g0.set(l, dt * co.g0);
    k.af.set(l, co.alpha_f);
    k.b1_dt2.set(l, co.b1 * dt2);
    k.g1_dt.set(l, co.g1 * dt);
    k.b1_dt_dt.set(l, co.b1 * dt * dt);
    k.minus_am.set(l, -co.alpha_m);
    k.mass_term.set(l, co.alpha_m != 0.0);
    k.one_minus_w.set(l, 1.0 - co.contact_weight);
    k.w.set(l, co.contact_weight);

    b.primary[lane] = scenes[lane]->primary;
    RunSummary& summary = summaries[lane];
    LaneRun& run = b.lanes[lane];
    run.summary = &summary;
    run.trace = &traces[lane];
    run.first = summary.skipped_steps;
    run.last = scenes[lane]->step_count - 1;
    run.energy_bound = options.energy_growth_limit * summary.initial_energy;
  }
  const std::vector<RowBlock> blocks = row_blocks(x, force_rows);
  x.blocks = blocks.data();
  x.block_count = static_cast<int>(blocks.size());
  run_chain_any(b);
  for (int l = 0; l < count; ++l) {
    if (running[l]) summaries[static_cast<std::size_t>(l)].max_penetration = b.penetration[l];
  }

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int l = 0; l < count; ++l)
    summaries[static_cast<std::size_t>(l)].wall_time_s = seconds / count;
}

}  // namespace

void simulate_chain_lanes(std::span<const AssembledScene* const> scenes,
                          std::span<const MethodParams> methods, const RunOptions& options,
                          std::vector<LaneBlock>& storage, std::array<State, kBatchLanes>& starts,
                          std::array<ImplicitIntegrator, kBatchLanes>& integrators,
                          std::array<ContactTrace, kBatchLanes>& traces,
                          std::span<RunSummary> summaries) {
  for_each_sub_batch(scenes.size(), [&](std::size_t first, std::size_t count) {
    simulate_chain_sub_batch(scenes.subspan(first, count), methods.subspan(first, count), options,
                             storage, sub_batch_part(starts, first),
                             sub_batch_part(integrators, first), sub_batch_part(traces, first),
                             summaries.subspan(first, count));
  });
}

}  // namespace impactid::IMPACTID_KERNEL_NAMESPACE
