#include "study/cli/run_command.hpp"

#include <omp.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <memory>
#include <numeric>
#include <optional>
#include <span>

#include "study/cli/command_line.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/formats/utc_time.hpp"
#include "study/io/history_file.hpp"
#include "study/io/results_file.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/optimizer.hpp"
#include "study/studies/practical_range.hpp"
#include "study/studies/shard.hpp"
#include "study/studies/spectral_study.hpp"
#include "study/studies/sweep.hpp"
#include "study/studies/work_precision.hpp"
#include "study/version.hpp"

namespace impactid {
namespace {

// Set by SIGINT/SIGTERM/SIGUSR1. The one mutable global of the program: a signal handler can reach
// nothing else. Lock-free, so setting it is async-signal-safe.
std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void request_stop(int) {
  g_stop_requested.store(true);
}

constexpr int kExitInterrupted = 130;

// While it lives, SIGINT, SIGTERM and SIGUSR1 ask the running study to stop (g_stop_requested)
// rather than kill the process; the previous handlers come back when it goes, on every path out
// (the defaults in the program; Python's own when `import impactid` runs a plan). SIGUSR1 is
// the one a batch system can send ahead of a job's end (Slurm's `--signal=USR1@SECONDS`) and the
// one mpirun passes on to its ranks: SIGINT and SIGTERM to mpirun end the ranks outright.
class StopOnSignals {
 public:
  StopOnSignals() {
    g_stop_requested.store(false);
    struct sigaction stop {};
    stop.sa_handler = request_stop;
    sigemptyset(&stop.sa_mask);
    stop.sa_flags = SA_RESTART;  // as std::signal had it: a checkpoint's write is not cut short
    sigaction(SIGINT, &stop, &previous_int_);
    sigaction(SIGTERM, &stop, &previous_term_);
    sigaction(SIGUSR1, &stop, &previous_usr1_);
  }
  ~StopOnSignals() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
    sigaction(SIGUSR1, &previous_usr1_, nullptr);
  }
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
  struct sigaction previous_usr1_ {};
};

std::string duration_text(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600) {
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld", s / 60, s % 60);
  }
  return buffer;
}

void stamp(StudyResults& r, int threads, double wall_time_s) {
  r.impactid_version = kVersion;
  r.git_revision = kGitRevision;
  r.threads = threads;
  r.wall_time_s = wall_time_s;
  r.date = utc_now();
}

// The points of the table (or those of `indices`) that ran and are not ok (unstable, failed):
// the reused ones of a resumed file count as well as those computed now.
long count_not_ok(const StudyResults& r) {
  return static_cast<long>(
      std::count_if(r.status.begin(), r.status.end(), [](int status) { return status > 0; }));
}
long count_not_ok(const StudyResults& r, std::span<const long> indices) {
  return static_cast<long>(std::count_if(indices.begin(), indices.end(), [&](long i) {
    return r.status[static_cast<std::size_t>(i)] > 0;
  }));
}

// Where a plan's `[output] histories` go: the plan's folder, or with --output FILE the folder
// FILE's name gives, beside it (results/x.h5 -> results/x-histories), so that --output places
// everything a run writes.
std::filesystem::path histories_folder(const Plan& plan, const std::string& output) {
  if (output.empty()) return *plan.output.histories;
  const std::filesystem::path file(output);
  return file.parent_path() / (file.stem().string() + "-histories");
}

// --dry-run's estimate of a grid or list: a pilot, a short run of part of the plan, timed.
//
// The pilot is whole windows of kBatchLanes points (the sweep's unit of work), spread evenly over
// the plan because cost varies along an axis (an unstable point stops early, a finer mesh costs
// more), run by run_sweep on the plan's threads as the real run runs them, batched kernels
// included, into a table that is thrown away. Timing points one at a time through simulate()
// instead once estimated 0:08 for a sweep that took 36.8 s: the batched kernels, the threads'
// sharing of cores and the windows' scheduling were not in the measurement.
//
// It runs in rounds, one window per thread and then twice as many each round, each round's
// windows halfway between the earlier ones, until half of kPilotSeconds has passed (so about a
// second in all) or every window has run. When one point (of the first, middle and last) takes
// so long that a window would exceed kPilotSeconds (a large model), the pilot is instead a few
// points one at a time, spread over the plan, until kPilotSeconds have passed; the text says
// which.
struct Pilot {
  long points = 0;   ///< points the pilot ran
  long windows = 0;  ///< windows of kBatchLanes points, or 0: points one at a time
  long not_ok = 0;   ///< of them, unstable or failed (and so stopped early)
  double seconds = 0.0;
};

constexpr double kPilotSeconds = 1.0;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Pilot one_at_a_time(const PointSet& points) {
  constexpr long kMaxPoints = 16;
  const long n = points.size();
  const long wanted = std::min(n, kMaxPoints);
  SimulationWorkspace workspace;
  Pilot pilot;
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < wanted && (k == 0 || pilot.seconds < kPilotSeconds); ++k) {
    const long index = wanted == 1 ? 0 : k * (n - 1) / (wanted - 1);
    const Evaluation e = evaluate(std::get<Simulation>(build(points.settings(index))), workspace);
    ++pilot.points;
    if (e.summary.status != RunStatus::ok) ++pilot.not_ok;
    pilot.seconds = seconds_since(start);
  }
  return pilot;
}

// The windows 0..count-1 in an order of which every beginning is spread over all of them: the
// first, then those at 1/2, then at 1/4 and 3/4, ...
std::vector<long> spread_order(long count) {
  std::vector<long> order;
  std::vector<bool> taken(static_cast<std::size_t>(count), false);
  for (long parts = 1; static_cast<long>(order.size()) < count; parts *= 2) {
    for (long k = 0; k < parts; ++k) {
      const long w = k * count / parts;
      if (!taken[static_cast<std::size_t>(w)]) {
        taken[static_cast<std::size_t>(w)] = true;
        order.push_back(w);
      }
    }
  }
  return order;
}

Pilot run_pilot(const Plan& plan, const PointSet& points, int threads) {
  const long n = points.size();
  {
    // The first, middle and last points, one at a time, say whether a window is affordable (one
    // alone could be an unstable point that stopped at once).
    SimulationWorkspace workspace;
    for (const long index : {0L, n / 2, n - 1}) {
      const auto start = std::chrono::steady_clock::now();
      evaluate(std::get<Simulation>(build(points.settings(index))), workspace);
      if (seconds_since(start) * kBatchLanes > kPilotSeconds) return one_at_a_time(points);
    }
  }
  const long total_windows = (n + kBatchLanes - 1) / kBatchLanes;
  const std::vector<long> order = spread_order(total_windows);
  StudyResults results = empty_results(plan, points);
  SweepOptions options;
  options.threads = threads;
  Pilot pilot;
  std::size_t next = 0;
  for (long round = threads; next < order.size() && pilot.seconds < kPilotSeconds / 2; round *= 2) {
    std::vector<long> windows(
        order.begin() + static_cast<long>(next),
        order.begin() +
            static_cast<long>(std::min(order.size(), next + static_cast<std::size_t>(round))));
    next += windows.size();
    std::sort(windows.begin(), windows.end());  // a short last window of the plan comes last
    std::vector<long> indices;
    for (const long w : windows) {
      for (long i = w * kBatchLanes; i < std::min(n, (w + 1) * kBatchLanes); ++i) {
        indices.push_back(i);
      }
    }
    pilot.seconds += run_sweep(points, indices, results, options).wall_time_s;
    pilot.points += static_cast<long>(indices.size());
    pilot.windows += static_cast<long>(windows.size());
    pilot.not_ok += count_not_ok(results, indices);
  }
  return pilot;
}

// What a spectral study computes; it takes seconds, so there is no estimate to measure.
int dry_run_spectral(const Plan& plan, const std::filesystem::path& output) {
  const SpectralStudy& s = plan.spectral;
  std::printf("plan        %s (spectral study)\n", plan.path.string().c_str());
  std::printf("output      %s\n", output.string().c_str());
  for (const SpectralMethod& m : s.methods) std::printf("method      %s\n", m.label.c_str());
  std::printf(
      "omega_dt    %4zu values from %g to %g: spectral_radius, damping_ratio, "
      "period_error per method; rho_inf and period_error_coefficient per method\n",
      s.omega_dt.size(), s.omega_dt.front(), s.omega_dt.back());
  std::printf(
      "alpha       %4zu values from %g to %g: HHT delta minimising the period error "
      "as omega_dt -> 0 and at omega_dt = %g\n",
      s.alpha.size(), s.alpha.front(), s.alpha.back(), s.omega_dt_reference);
  std::printf(
      "delta       %4zu values from %g to %g: HHT stability map over (alpha, delta), "
      "omega_dt up to %g\n",
      s.delta.size(), s.delta.front(), s.delta.back(), s.stability_omega_max);
  std::printf("evaluations %ld amplification matrices for the stability map\n",
              stability_map_evaluations(s));
  return 0;
}

// A work-precision study: its methods, meshes and Courant numbers, and an estimate from one
// timed run scaled by the cost model work ∝ elements²/courant (steps ∝ n/C, each O(n)).
int dry_run_work_precision(const Plan& plan, const std::filesystem::path& output) {
  const WorkPrecisionStudy& wp = plan.work_precision;
  std::printf("plan        %s (work-precision study)\n", plan.path.string().c_str());
  std::printf("output      %s\n", output.string().c_str());
  for (const SpectralMethod& m : wp.methods) std::printf("method      %s\n", m.label.c_str());
  std::string elements, courant;
  for (const long n : wp.elements) elements += " " + std::to_string(n);
  for (const double c : wp.courant) courant += " " + format_value(c);
  std::printf("elements   %s\n", elements.c_str());
  std::printf("courant    %s\n", courant.c_str());
  const long points = static_cast<long>(wp.methods.size() * wp.elements.size() * wp.courant.size());
  std::printf("points      %ld, each run %d times (the minimum time is kept), one at a time\n",
              points, wp.repeats);
  const long n0 = wp.elements.front();
  const double c0 = wp.courant.front();
  SimulationWorkspace workspace;
  const Simulation simulation =
      std::get<Simulation>(build(work_precision_settings(plan, 0, n0, c0)));
  evaluate(simulation, workspace);  // warm-up: allocation
  const double t = evaluate(simulation, workspace).summary.wall_time_s;
  double cost = 0.0;
  for (const long n : wp.elements) {
    for (const double c : wp.courant) {
      cost += (static_cast<double>(n) * n / c) / (static_cast<double>(n0) * n0 / c0);
    }
  }
  std::printf(
      "estimate    %s (%.3g s measured at %s, elements %ld, courant %g, scaled by "
      "elements^2/courant; unstable runs stop early)\n",
      duration_text(t * cost * static_cast<double>(wp.methods.size()) * wp.repeats).c_str(), t,
      wp.methods.front().label.c_str(), n0, c0);
  return 0;
}

// `output_argument`: --output as given ("" when not), which places the histories too.
int dry_run(const Plan& plan, int threads, const std::filesystem::path& output,
            const std::string& output_argument) {
  if (plan.kind == StudyKind::spectral) return dry_run_spectral(plan, output);
  if (plan.kind == StudyKind::work_precision) return dry_run_work_precision(plan, output);
  std::printf("plan        %s (%s study, method %s)\n", plan.path.string().c_str(),
              to_string(plan.kind), to_string(plan.base.method.kind));
  std::printf("output      %s\n", output.string().c_str());
  if (plan.kind == StudyKind::optimize) {
    for (const OptimizeParameter& p : plan.optimize.parameters) {
      std::printf("parameter   %s in [%g, %g]\n", p.name.c_str(), p.lower, p.upper);
    }
    // Time one evaluation at the start point (the base alone need not build: e.g. Newmark
    // with beta fixed and gamma optimised).
    SimulationSettings start_point = plan.base;
    for (const OptimizeParameter& p : plan.optimize.parameters) {
      assign(start_point, p.name, p.initial());
    }
    SimulationWorkspace workspace;
    const auto start = std::chrono::steady_clock::now();
    evaluate(std::get<Simulation>(build(start_point)), workspace);
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long starts = plan.optimize.starts;
    const long waves = (starts + threads - 1) / threads;  // searches one after another
    if (starts == 1) {
      std::printf("evaluations at most %ld (%s), one at a time\n", plan.optimize.max_evaluations,
                  plan.optimize.algorithm.c_str());
    } else {
      std::printf("evaluations at most %ld (%s): %ld searches of %ld, %ld at a time\n",
                  starts * plan.optimize.max_evaluations, plan.optimize.algorithm.c_str(), starts,
                  plan.optimize.max_evaluations, std::min<long>(starts, threads));
    }
    std::printf(
        "estimate    %s (%.3g s per evaluation, measured on the start point)\n",
        duration_text(t * static_cast<double>(waves * plan.optimize.max_evaluations)).c_str(), t);
    return 0;
  }
  const PointSet points(plan);
  for (std::size_t d = 0; d < points.dimension_names().size(); ++d) {
    const auto& values = points.dimension_values()[d];
    std::printf("axis        %-12s %4zu values from %g to %g\n",
                points.dimension_names()[d].c_str(), values.size(), values.front(), values.back());
  }
  for (const CoupledAxis& c : plan.coupled) {
    std::printf("coupled     %-12s = %s\n", c.name.c_str(), c.expression.text().c_str());
  }
  std::printf("points      %ld\n", points.size());
  if (plan.output.histories) {
    std::printf("histories   %s/point-<index>.h5\n",
                histories_folder(plan, output_argument).string().c_str());
  }
  if (!plan.practical.empty()) {
    std::printf("practical   %s\n", thresholds_text(plan.practical).c_str());
  }
  const Pilot pilot = run_pilot(plan, points, threads);
  const double n = static_cast<double>(points.size());
  // Points that are not ok stop early; the pilot, spread over the plan, has its share of them.
  const std::string not_ok =
      pilot.not_ok > 0 ? "; " + std::to_string(pilot.not_ok) + " of them not ok" : "";
  if (pilot.windows > 0) {
    std::printf(
        "estimate    %s on %d thread(s), from a pilot run: %ld of the %ld points (%ld window%s "
        "of %ld spread over the plan) run as the sweep runs them, on %d thread(s), in %.3g s%s\n",
        duration_text(pilot.seconds * n / static_cast<double>(pilot.points)).c_str(), threads,
        pilot.points, points.size(), pilot.windows, pilot.windows == 1 ? "" : "s",
        static_cast<long>(kBatchLanes), threads, pilot.seconds, not_ok.c_str());
  } else {
    const double per_point = pilot.seconds / static_cast<double>(pilot.points);
    std::printf(
        "estimate    %s on %d thread(s), from a pilot run: %ld of the %ld points spread over "
        "the plan, run one at a time in %.3g s (%.3g s per point; the sweep runs %d at a "
        "time)%s\n",
        duration_text(per_point * n / threads).c_str(), threads, pilot.points, points.size(),
        pilot.seconds, per_point, threads, not_ok.c_str());
  }
  return 0;
}

// Reads an existing results file; a file that exists but cannot be read is never overwritten
// (`unreadable`, and the reason on stderr).
std::optional<StudyResults> existing_results(const std::filesystem::path& output,
                                             bool& unreadable) {
  unreadable = false;
  if (!std::filesystem::exists(output)) return std::nullopt;
  try {
    return read_results(output);
  } catch (const std::exception& e) {
    unreadable = true;
    std::cerr << "impactid run: " << e.what() << "\nimpactid run: " << output.string()
              << " exists but is not a readable impactid results file; it was left untouched "
                 "(remove it, or choose another file with --output)\n";
    return std::nullopt;
  }
}

// The time histories of every point, one file each, for plots of the signals themselves
// (a sweep keeps only indicators). Serial: lists of this kind are short.
void write_point_histories(const PointSet& points, std::span<const long> indices,
                           const std::filesystem::path& folder) {
  SimulationWorkspace workspace;
  for (const long index : indices) {
    Simulation simulation = std::get<Simulation>(build(points.settings(index)));
    simulation.run.record_history = true;
    evaluate(simulation, workspace);  // the rod's or a scene of bodies' run, as the sweep's
    write_history(folder / ("point-" + std::to_string(index) + ".h5"), simulation, workspace.trace,
                  simulation.model() ? &*workspace.model_reference : nullptr);
  }
  std::fprintf(stderr, "impactid run: wrote the time histories of %zu points to %s/\n",
               indices.size(), folder.string().c_str());
}

// The last line of a run that was stopped: how to continue it. Returns the exit status.
// A shard's file is named in full (its name may be derived from --output).
int report_interrupted(const RunArguments& args, const Runners& runners,
                       std::optional<Shard> shard = std::nullopt,
                       const std::filesystem::path& output = {}) {
  const std::string file = shard ? output.string() : args.output;
  std::fprintf(stderr, "impactid run: interrupted; continue with: %s %s%s --resume%s\n",
               runners.resume_command.c_str(), args.plan.c_str(),
               shard ? (" --shard " + to_string(*shard)).c_str() : "",
               file.empty() ? "" : (" --output " + file).c_str());
  return kExitInterrupted;
}

// A spectral study: no simulation, no checkpoints; computed in full every time (--resume too),
// in seconds. Like a results file, an existing file of another kind is never overwritten.
int run_spectral(const Plan& plan, const RunArguments& args, const std::filesystem::path& output,
                 int threads) {
  if (std::filesystem::exists(output) && !is_spectral_results_file(output)) {
    std::cerr << "impactid run: " << output.string()
              << " exists but is not an impactid spectral results file; it was left untouched "
                 "(remove it, or choose another file with --output)\n";
    return kExitFailure;
  }
  if (args.resume) {
    std::fprintf(stderr, "impactid run: --resume: a spectral study is recomputed in full\n");
  }
  const auto start = std::chrono::steady_clock::now();
  SpectralResults r = compute_spectral_study(plan.spectral, threads);
  r.plan_name = plan.name;
  r.plan_text = plan.text;
  r.impactid_version = kVersion;
  r.git_revision = kGitRevision;
  r.date = utc_now();
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  try {
    write_spectral_results(output, r);
  } catch (const std::exception& e) {
    std::cerr << "impactid run: " << e.what() << '\n';
    return kExitFailure;
  }
  std::fprintf(stderr,
               "impactid run: %s: spectral study of %zu methods at %zu omega_dt values, "
               "delta_min over %zu alpha, stability map %zu x %zu; %.3g s on %d thread(s); "
               "wrote %s\n",
               plan.name.c_str(), r.method_label.size(), r.omega_dt.size(), r.alpha.size(),
               r.alpha.size(), r.delta.size(), r.wall_time_s, threads, output.string().c_str());
  return 0;
}

class ProgressLine {
 public:
  explicit ProgressLine(std::string label) : label_(std::move(label)), tty_(isatty(2)) {}
  void update(long done, long total, long unstable, double elapsed) {
    if (!tty_) return;
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    const double eta = rate > 0 ? (total - done) / rate : NAN;
    std::fprintf(stderr, "\r%s %ld/%ld (%3.0f%%)  %.1f/s  ETA %s  unstable %ld   ", label_.c_str(),
                 done, total, total ? 100.0 * done / total : 100.0, rate,
                 duration_text(eta).c_str(), unstable);
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fputc('\n', stderr);
  }

 private:
  std::string label_;
  bool tty_;
  bool shown_ = false;
};

// A work-precision study: serial by design (study/studies/work_precision.hpp says why), with
// checkpoints, progress and --resume as a grid has them.
int run_work_precision_plan(const Plan& plan, const RunArguments& args, const Runners& runners,
                            const std::filesystem::path& output) {
  bool unreadable = false;
  std::optional<StudyResults> previous = existing_results(output, unreadable);
  if (unreadable) return kExitFailure;
  StudyResults results = empty_work_precision_results(plan);
  if (args.resume && previous) {
    bool same = previous->plan_text == plan.text &&
                previous->dimensions.size() == results.dimensions.size();
    for (std::size_t d = 0; same && d < results.dimensions.size(); ++d) {
      same = previous->dimensions[d].name == results.dimensions[d].name &&
             previous->dimensions[d].values == results.dimensions[d].values;
    }
    if (!same) {
      std::cerr << "impactid run: --resume: " << output.string()
                << " was written by a different plan (the plan text or its points differ); it "
                   "was left untouched\n";
      return kExitBadInput;
    }
    results = std::move(*previous);
  }
  const double previous_wall_time = args.resume && previous ? results.wall_time_s : 0.0;

  std::optional<StopOnSignals> stop_on_signals(std::in_place);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const auto save = [&](StudyResults r) {
    stamp(r, 1, previous_wall_time + elapsed());
    write_results(output, r);
  };
  ProgressLine progress(plan.name);
  WorkPrecisionOptions options;
  options.checkpoint_seconds = plan.output.checkpoint_seconds;
  options.checkpoint = [&](const StudyResults& r) { save(r); };
  options.progress = [&](const SweepProgress& p) {
    progress.update(p.done, p.total, p.unstable, p.elapsed_s);
  };
  options.stop = &g_stop_requested;
  SweepOutcome outcome;
  try {
    outcome = run_work_precision(plan, results, options);
    progress.finish();
    save(results);
    outcome.unstable = count_not_ok(results);  // the reused points' too
  } catch (const std::exception& e) {
    progress.finish();
    std::cerr << "impactid run: " << e.what() << '\n';
    return kExitFailure;
  }
  stop_on_signals.reset();
  std::fprintf(stderr,
               "impactid run: %s: work-precision, %ld computed, %ld reused, %ld not ok, of %ld; "
               "each run %d times, one at a time on 1 thread; %.3g s; wrote %s\n",
               plan.name.c_str(), outcome.computed, outcome.reused, outcome.unstable,
               results.points_total(), plan.work_precision.repeats, elapsed(),
               output.string().c_str());
  return outcome.interrupted ? report_interrupted(args, runners) : 0;
}

}  // namespace

int run_plan(const RunArguments& args, const Runners& runners) {
  Plan plan;
  try {
    plan = args.plan_text.empty() ? load_plan(args.plan) : parse_plan(args.plan_text, args.plan);
  } catch (const PlanError& e) {
    std::cerr << e.what() << '\n';
    return kExitBadInput;
  }
  // --shard K/N, or inside a Slurm array job the task's shard (study/studies/shard.hpp).
  std::optional<Shard> shard;
  try {
    shard = args.shard.empty() ? slurm_array_shard(std::getenv) : parse_shard(args.shard);
  } catch (const ShardError& e) {
    std::cerr << "impactid run: " << e.what() << '\n';
    return kExitBadInput;
  }
  if (shard && plan.kind != StudyKind::grid && plan.kind != StudyKind::list) {
    std::cerr << "impactid run: "
              << (args.shard.empty()
                      ? "in a Slurm array job (SLURM_ARRAY_TASK_ID is set), the task's shard"
                      : "--shard " + args.shard)
              << ": a " << to_string(plan.kind)
              << " study runs as a whole; only grid and list studies are split in shards\n";
    return kExitBadInput;
  }
  if (shard && args.shard.empty()) {
    std::fprintf(stderr, "impactid run: shard %s, from the Slurm array task\n",
                 to_string(*shard).c_str());
  }
  // A shard's default file is named after it. So is --output's in an array job (the shard from
  // Slurm): every task gets the same command line, and must not write the same file.
  std::filesystem::path output =
      args.output.empty() ? plan.output.file : std::filesystem::path(args.output);
  if (shard && (args.output.empty() || args.shard.empty())) output = shard_file(output, *shard);
  if (plan.kind == StudyKind::work_precision && args.threads > 1) {
    // Validate, never clamp: a silently serial run would not be what was asked for.
    std::cerr << "impactid run: --threads " << args.threads
              << ": a work-precision study times its runs one at a time on one thread (runs "
                 "sharing cores and caches would time each other); leave --threads out\n";
    return kExitBadInput;
  }
  const int threads = args.threads > 0 ? args.threads : omp_get_max_threads();
  if (args.dry_run) return dry_run(plan, threads, output, args.output);
  if (plan.kind == StudyKind::work_precision)
    return run_work_precision_plan(plan, args, runners, output);
  if (plan.kind == StudyKind::spectral) return run_spectral(plan, args, output, threads);

  bool unreadable = false;
  std::optional<StudyResults> previous = existing_results(output, unreadable);
  if (unreadable) return kExitFailure;
  if (args.resume && previous && previous->plan_text != plan.text) {
    std::cerr << "impactid run: --resume: " << output.string()
              << " was written by a different plan (the plan text differs); it was left "
                 "untouched\n";
    return kExitBadInput;
  }
  if (args.resume && previous && plan.kind != StudyKind::optimize) {
    // Same text, but another program version could expand it differently: compare the grid.
    const PointSet points(plan);
    bool same = previous->dimensions.size() == points.dimension_names().size();
    for (std::size_t d = 0; same && d < previous->dimensions.size(); ++d) {
      same = previous->dimensions[d].name == points.dimension_names()[d] &&
             previous->dimensions[d].values == points.dimension_values()[d] &&
             previous->dimensions[d].labels == points.dimension_labels()[d];
    }
    if (!same) {
      std::cerr << "impactid run: --resume: the points of " << output.string()
                << " differ from those of the plan; it was left untouched\n";
      return kExitBadInput;
    }
    std::optional<ShardMark> mark;
    try {
      mark = shard_mark(*previous);
    } catch (const ShardError& e) {
      std::cerr << "impactid run: --resume: " << output.string() << ": " << e.what() << '\n';
      return kExitBadInput;
    }
    if ((mark ? std::optional(mark->shard) : std::nullopt) != shard) {
      std::cerr << "impactid run: --resume: " << output.string() << " holds "
                << (mark ? "shard " + to_string(mark->shard) : std::string("the whole plan"))
                << ", not "
                << (shard ? "shard " + to_string(*shard) : std::string("the whole plan"))
                << "; it was left untouched\n";
      return kExitBadInput;
    }
  }
  // A shard's file is the only record of its points until the merge: a run that would replace
  // one with another shard's, or with another plan's (the same --output given to every shard
  // by mistake), is refused unless --force says it is meant.
  if (!args.resume && previous && !args.force) {
    std::optional<ShardMark> mark;
    try {
      mark = shard_mark(*previous);
    } catch (const ShardError&) {
    }
    if (mark && (mark->shard != shard || previous->plan_text != plan.text)) {
      std::cerr << "impactid run: " << output.string() << " holds shard "
                << to_string(mark->shard)
                << (previous->plan_text != plan.text ? " of another plan" : "") << ", not "
                << (shard ? "shard " + to_string(*shard) : std::string("the whole plan"))
                << "; it was left untouched (give each shard its own file: leave --output "
                   "out, or --force to replace it)\n";
      return kExitFailure;
    }
  }
  if (!args.resume) previous.reset();
  const double previous_wall_time = previous ? previous->wall_time_s : 0.0;

  std::optional<StopOnSignals> stop_on_signals(std::in_place);
  const auto save = [&](StudyResults results, double wall_time_s) {
    stamp(results, threads, previous_wall_time + wall_time_s);
    if (shard) {
      write_results_compressed(output, results);  // the other shards' points are NaN
    } else {
      write_results(output, results);
    }
  };
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  ProgressLine progress(plan.name);

  long computed = 0, reused = 0, unstable = 0, total = 0;
  bool interrupted = false;
  std::string extra;
  try {
    if (plan.kind == StudyKind::optimize) {
      OptimizeOptions options;
      options.threads = threads;
      options.searches = runners.searches;
      options.checkpoint_seconds = plan.output.checkpoint_seconds;
      options.checkpoint = [&](const StudyResults& r) { save(r, elapsed()); };
      options.progress = [&](long done, long max, long unstable, double) {
        progress.update(done, max, unstable, elapsed());
      };
      options.stop = &g_stop_requested;
      options.previous = previous ? &*previous : nullptr;
      OptimizeOutcome outcome = run_optimization(plan, options);
      progress.finish();
      save(outcome.results, elapsed());
      computed = outcome.computed;
      reused = outcome.reused;
      unstable = count_not_ok(outcome.results);
      total = outcome.results.points_total();
      interrupted = outcome.interrupted;
      extra = "termination " + outcome.termination + "; ";
      if (outcome.best) {
        extra += "best feasible evaluation #" + std::to_string(*outcome.best) + ":";
        for (const auto& [name, value] : outcome.results.numeric_attributes) {
          if (name.rfind("best_", 0) == 0 && name != "best_evaluation") {
            const std::string key = name.substr(5);
            const bool is_param =
                std::any_of(plan.optimize.parameters.begin(), plan.optimize.parameters.end(),
                            [&](const OptimizeParameter& p) { return p.name == key; });
            if (is_param || key == "objective") extra += " " + key + " = " + format_value(value);
          }
        }
      } else {
        extra += "no feasible evaluation";
      }
    } else {
      const PointSet points(plan);
      StudyResults results = previous ? std::move(*previous) : empty_results(plan, points);
      // The practical range is derived from the rest of the table: recomputed below.
      remove_practical_range(results);
      std::vector<long> indices;
      if (shard) {
        indices = shard_points(points.size(), *shard);
        mark_shard(results, *shard, plan.path);
      } else {
        indices.resize(static_cast<std::size_t>(points.size()));
        std::iota(indices.begin(), indices.end(), 0L);
      }
      SweepOptions options;
      options.threads = threads;
      options.checkpoint_seconds = plan.output.checkpoint_seconds;
      options.checkpoint = [&](const StudyResults& r) { save(r, elapsed()); };
      options.progress = [&](const SweepProgress& p) {
        progress.update(p.done, p.total, p.unstable, p.elapsed_s);
      };
      options.stop = &g_stop_requested;
      const SweepOutcome outcome = runners.sweep
                                       ? runners.sweep(plan, points, indices, results, options)
                                       : run_sweep(points, indices, results, options);
      progress.finish();
      if (!plan.practical.empty() && shard) {
        std::fprintf(stderr,
                     "impactid run: practical range: computed by impactid merge over "
                     "every shard\n");
      } else if (!plan.practical.empty()) {
        const PracticalRange range = practical_range(results, plan.practical);
        store_practical_range(results, range);
        std::fprintf(stderr, "impactid run: practical range (%s): %s\n", range.thresholds.c_str(),
                     practical_summary(range).c_str());
      }
      const long not_ok = count_not_ok(results, indices);
      if (const std::string verdicts = verdict_summary(results); !verdicts.empty()) {
        std::fprintf(stderr, "impactid run: verdicts (accurate within %s): %s\n",
                     thresholds_text(plan.base.verdict).c_str(), verdicts.c_str());
      }
      save(std::move(results), elapsed());
      if (plan.output.histories && !outcome.interrupted) {
        write_point_histories(points, indices, histories_folder(plan, args.output));
      }
      computed = outcome.computed;
      reused = outcome.reused;
      unstable = not_ok;
      total = static_cast<long>(indices.size());
      interrupted = outcome.interrupted;
    }
  } catch (const std::exception& e) {
    progress.finish();
    std::cerr << "impactid run: " << e.what() << '\n';
    return kExitFailure;
  }
  stop_on_signals.reset();

  const double seconds = elapsed();
  std::fprintf(stderr,
               "impactid run: %s%s: %ld computed, %ld reused, %ld not ok, of %ld; %.3g s on %d "
               "thread(s); %swrote %s\n",
               plan.name.c_str(), shard ? (" shard " + to_string(*shard)).c_str() : "", computed,
               reused, unstable, total, seconds, threads,
               extra.empty() ? "" : (extra + "; ").c_str(), output.string().c_str());
  return interrupted ? report_interrupted(args, runners, shard, output) : 0;
}

std::function<int()> add_run_command(CLI::App& app, Runners runners) {
  auto* command = app.add_subcommand("run",
                                     "Run a plan file (grid, list, optimize, spectral or "
                                     "work-precision study) and write its HDF5 results");
  auto args = std::make_shared<RunArguments>();
  command->add_option("plan", args->plan, "Plan file (TOML), see plans/README.md")
      ->required()
      ->type_name("PLAN.toml");
  command
      ->add_option("--threads", args->threads,
                   "OpenMP threads (default: all cores, or OMP_NUM_THREADS)")
      ->check(CLI::PositiveNumber)
      ->type_name("N");
  command
      ->add_option("--output", args->output,
                   "Results file (default: [output] file of the plan, or "
                   "results/<plan name>.h5); the plan's [output] histories then go beside it, "
                   "to <FILE without .h5>-histories/")
      ->type_name("FILE");
  command->add_flag("--resume", args->resume,
                    "Keep the points already in the results file; compute only the rest");
  command->add_flag("--force", args->force,
                    "Replace the results file even if it holds another shard's points");
  command
      ->add_option("--shard", args->shard,
                   "Compute only shard K of N (0 <= K < N: every N-th window of 16 points, "
                   "from the K-th) into its own file (default: <output>.shard-K-of-N.h5); "
                   "join the shards with impactid merge. Default inside a Slurm array job: "
                   "the task's shard, from SLURM_ARRAY_TASK_ID, _MIN, _STEP and _COUNT, "
                   "written to <output>.shard-K-of-N.h5 also when --output is given")
      ->type_name("K/N");
  command->add_flag("--dry-run", args->dry_run,
                    "Print the points per axis and in total, and a time estimate from a pilot "
                    "run (a part of the plan, run and timed); write nothing");
  if (runners.add_options) runners.add_options(*command);
  return [command, args, runners = std::move(runners)]() -> int {
    if (!command->parsed()) return -1;
    return run_plan(*args, runners);
  };
}

}  // namespace impactid
