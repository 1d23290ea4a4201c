#include "study/studies/optimizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <nlopt.hpp>
#include <numeric>
#include <stdexcept>

#include "metrics/indicator_table.hpp"
#include "study/studies/evaluation.hpp"
#include "study/studies/first_failure.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool supports_inequality_constraints(nlopt::algorithm a) {
  return a == nlopt::LN_COBYLA || a == nlopt::GN_ISRES || a == nlopt::GN_ORIG_DIRECT ||
         a == nlopt::GN_ORIG_DIRECT_L;
}

// Search `start`'s evaluations as NLopt asks for them: its callbacks land here. record()
// and rows() hold the mutex, so another thread can copy the rows of a search in progress.
class Search {
 public:
  /// Called after each evaluation with its row's status: ok, and feasible.
  using Observer = std::function<void(bool ok, bool feasible, double objective)>;

  Search(const Plan& plan, const StudyResults* previous, const std::atomic<bool>* stop,
         Observer observer)
      : plan_(plan),
        previous_(previous),
        stop_(stop),
        observer_(std::move(observer)),
        rows_(empty_search_rows(plan)) {}

  // Evaluates x (or replays it), records it, and returns its index in the table.
  std::size_t evaluate_at(const double* x) {
    const std::size_t n = plan_.optimize.parameters.size();
    if (last_ && std::equal(x, x + n, last_x_.begin())) return *last_;
    if (stop_ && stop_->load()) {
      interrupted_ = true;
      throw nlopt::forced_stop();
    }
    if (static_cast<long>(rows_.status.size()) >= plan_.optimize.max_evaluations) {
      budget_exhausted_ = true;  // AUGLAG's subsidiary runs can overrun NLopt's own count
      throw nlopt::forced_stop();
    }
    last_x_.assign(x, x + n);
    const std::size_t row = rows_.status.size();
    if (!replay(x, row)) compute(x);
    last_ = row;
    return row;
  }

  double objective(std::size_t row) const { return objective_[row]; }
  double constraint(std::size_t row, std::size_t j) const { return violations_[row][j]; }

  /// The rows so far; while replay has not caught up with the previous run's rows (and has
  /// not left them), those: a checkpoint then loses nothing of the earlier run.
  StudyResults rows() const {
    std::lock_guard lock(mutex_);
    if (previous_ && !diverged_ && previous_->status.size() > rows_.status.size()) {
      return *previous_;
    }
    return rows_;
  }

  SearchOutcome outcome(std::string termination) {
    std::lock_guard lock(mutex_);
    return {std::move(rows_), std::move(termination), computed_, reused_, interrupted_};
  }

  bool budget_exhausted() const { return budget_exhausted_; }

 private:
  ResultColumn& column(const std::string& name) { return *rows_.find_column(name); }

  // Re-uses the previous run's row `row` if it was computed at exactly this x.
  bool replay(const double* x, std::size_t row) {
    const StudyResults* prev = previous_;
    if (!prev || diverged_ || row >= prev->status.size()) return false;
    for (std::size_t k = 0; k < plan_.optimize.parameters.size(); ++k) {
      const ResultColumn* c = prev->find_column(plan_.optimize.parameters[k].name);
      if (!c || c->values[row] != x[k]) {
        std::lock_guard lock(mutex_);
        diverged_ = true;
        return false;
      }
    }
    Evaluation e;
    e.summary.status = static_cast<RunStatus>(prev->status[row]);
    const auto get = [&](const char* name) {
      const ResultColumn* c = prev->find_column(name);
      return c ? c->values[row] : kNaN;
    };
    for (const IndicatorInfo& info : indicator_table()) info.field(e) = get(info.name);
    std::vector<double> params;
    for (const ResultColumn& c : rows_.parameters) params.push_back(get(c.name.c_str()));
    record(e, params);
    ++reused_;
    return true;
  }

  void compute(const double* x) {
    SimulationSettings settings = plan_.base;
    for (std::size_t k = 0; k < plan_.optimize.parameters.size(); ++k) {
      assign(settings, plan_.optimize.parameters[k].name, x[k]);
    }
    auto built = build(settings);
    std::vector<double> params;
    Evaluation e;
    if (auto* sim = std::get_if<Simulation>(&built)) {
      e = evaluate(*sim, workspace_);
      for (const ResultColumn& c : rows_.parameters) {
        params.push_back(numeric_value(*sim, c.name).value_or(kNaN));
      }
    } else {
      // NLopt stays inside the bounds that load_plan() checked, so this is a defect.
      e.summary.status = RunStatus::failed;
      e.indicators = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
      params.assign(rows_.parameters.size(), kNaN);
    }
    record(e, params);
    ++computed_;
  }

  void record(const Evaluation& e, const std::vector<double>& params) {
    const bool ok = e.summary.status == RunStatus::ok;
    double objective = 0.0;
    for (const auto& [name, weight] : plan_.optimize.objective) {
      objective += weight * find_indicator(name)->value(e);
    }
    if (!ok || !std::isfinite(objective)) objective = kPenalty;
    std::vector<double> violations;
    bool feasible = ok;
    for (const IndicatorConstraint& c : plan_.optimize.constraints) {
      const double v = find_indicator(c.indicator)->value(e);
      if (c.max) violations.push_back(ok && std::isfinite(v) ? v - *c.max : kPenalty);
      if (c.min) violations.push_back(ok && std::isfinite(v) ? *c.min - v : kPenalty);
    }
    for (const double v : violations) feasible = feasible && v <= 0.0;
    violations_.push_back(std::move(violations));
    objective_.push_back(objective);
    {
      std::lock_guard lock(mutex_);
      const std::size_t row = rows_.status.size();
      rows_.status.push_back(static_cast<int>(e.summary.status));
      rows_.dimensions[0].values.push_back(static_cast<double>(row));
      for (std::size_t k = 0; k < params.size(); ++k) {
        rows_.parameters[k].values.push_back(params[k]);
      }
      for (const IndicatorInfo& info : indicator_table()) {
        column(info.name).values.push_back(info.value(e));
      }
      column("objective").values.push_back(objective);
      column("feasible").values.push_back(feasible ? 1.0 : 0.0);
    }
    if (observer_) observer_(ok, feasible, objective);
  }

  const Plan& plan_;
  const StudyResults* previous_;
  const std::atomic<bool>* stop_;
  Observer observer_;
  mutable std::mutex mutex_;  // guards rows_ and diverged_ against rows() from other threads
  StudyResults rows_;
  std::vector<double> objective_;
  std::vector<std::vector<double>> violations_;
  SimulationWorkspace workspace_;
  std::optional<std::size_t> last_;
  std::vector<double> last_x_;
  long computed_ = 0, reused_ = 0;
  bool diverged_ = false, interrupted_ = false, budget_exhausted_ = false;
};

struct ConstraintData {
  Search* search;
  std::size_t index;
};

double objective_callback(unsigned, const double* x, double*, void* data) {
  auto* search = static_cast<Search*>(data);
  return search->objective(search->evaluate_at(x));
}

double constraint_callback(unsigned, const double* x, double*, void* data) {
  auto* c = static_cast<ConstraintData*>(data);
  return c->search->constraint(c->search->evaluate_at(x), c->index);
}

const char* result_name(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS:
      return "SUCCESS";
    case nlopt::STOPVAL_REACHED:
      return "STOPVAL_REACHED";
    case nlopt::FTOL_REACHED:
      return "FTOL_REACHED";
    case nlopt::XTOL_REACHED:
      return "XTOL_REACHED";
    case nlopt::MAXEVAL_REACHED:
      return "MAXEVAL_REACHED";
    case nlopt::MAXTIME_REACHED:
      return "MAXTIME_REACHED";
    default:
      return "FAILURE";
  }
}

// Runs NLopt for `search` from search `start`'s first point; returns the termination.
std::string run_nlopt(const Plan& plan, long start, Search& search) {
  const OptimizeStudy& study = plan.optimize;
  const auto n = static_cast<unsigned>(study.parameters.size());
  const nlopt::algorithm algorithm =
      static_cast<nlopt::algorithm>(nlopt_algorithm_from_string(study.algorithm.c_str()));

  std::vector<double> lower, upper;
  for (const OptimizeParameter& p : study.parameters) {
    lower.push_back(p.lower);
    upper.push_back(p.upper);
  }
  std::vector<double> x = start_point(study, start);

  std::size_t constraint_count = 0;
  for (const IndicatorConstraint& c : study.constraints) {
    constraint_count += (c.max ? 1 : 0) + (c.min ? 1 : 0);
  }
  const bool wrap = constraint_count > 0 && !supports_inequality_constraints(algorithm);
  nlopt::opt opt(wrap ? nlopt::AUGLAG : algorithm, n);
  if (wrap) {
    nlopt::opt local(algorithm, n);
    local.set_xtol_rel(study.xtol_rel);
    if (study.ftol_rel > 0) local.set_ftol_rel(study.ftol_rel);
    local.set_maxeval(static_cast<int>(study.max_evaluations));
    opt.set_local_optimizer(local);
  }
  // NLopt's generator is per thread (thread-local in its library), seeded here on the thread
  // that runs the search: the search repeats whichever thread runs it.
  nlopt::srand(study.seed + static_cast<unsigned long>(start));
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_min_objective(objective_callback, &search);
  std::vector<ConstraintData> constraint_data;
  constraint_data.reserve(constraint_count);
  for (std::size_t j = 0; j < constraint_count; ++j) {
    constraint_data.push_back({&search, j});
    opt.add_inequality_constraint(constraint_callback, &constraint_data.back(), 0.0);
  }
  opt.set_maxeval(static_cast<int>(study.max_evaluations));
  opt.set_xtol_rel(study.xtol_rel);
  if (study.ftol_rel > 0) opt.set_ftol_rel(study.ftol_rel);

  try {
    double f = 0.0;
    return result_name(opt.optimize(x, f));
  } catch (const nlopt::forced_stop&) {
    return search.budget_exhausted() ? "MAXEVAL_REACHED" : "FORCED_STOP";
  } catch (const nlopt::roundoff_limited&) {
    return "ROUNDOFF_LIMITED";
  } catch (const std::exception& e) {
    return std::string("FAILURE: ") + e.what();
  }
}

// The radical inverse of k in base b: k's digits mirrored behind the point (Halton 1964).
double radical_inverse(long k, long base) {
  double value = 0.0, scale = 1.0 / static_cast<double>(base);
  for (; k > 0; k /= base, scale /= static_cast<double>(base)) {
    value += static_cast<double>(k % base) * scale;
  }
  return value;
}

long nth_prime(std::size_t n) {  // 2, 3, 5, … (n from 0)
  long p = 1;
  for (std::size_t found = 0; found <= n;) {
    ++p;
    bool prime = true;
    for (long d = 2; d * d <= p && prime; ++d) prime = p % d != 0;
    if (prime) ++found;
  }
  return p;
}

// The previous run's rows of each search (all of a one-search file's rows are search 0's).
std::vector<StudyResults> rows_by_start(const Plan& plan, const StudyResults* previous) {
  std::vector<StudyResults> by_start(static_cast<std::size_t>(plan.optimize.starts),
                                     empty_search_rows(plan));
  if (!previous) return by_start;
  const ResultColumn* start = previous->find_column("start");
  for (std::size_t row = 0; row < previous->status.size(); ++row) {
    const double s = start ? start->values[row] : 0.0;
    if (!(s >= 0.0 && s < static_cast<double>(by_start.size()))) continue;
    StudyResults& out = by_start[static_cast<std::size_t>(s)];
    out.status.push_back(previous->status[row]);
    out.dimensions[0].values.push_back(static_cast<double>(out.dimensions[0].values.size()));
    for (auto* columns : {&out.parameters, &out.indicators}) {
      for (ResultColumn& c : *columns) {
        const ResultColumn* from = previous->find_column(c.name);
        c.values.push_back(from ? from->values[row] : kNaN);
      }
    }
  }
  return by_start;
}

// The searches' rows one after the other, as the results file holds them: the `start` column
// when there are several, the best feasible evaluation as root attributes.
StudyResults evaluations_table(const Plan& plan, std::span<const StudyResults> searches) {
  StudyResults r = empty_search_rows(plan);
  const bool several = plan.optimize.starts > 1;
  if (several) {
    r.parameters.push_back(
        {"start", "1", "the search: 0 from the plan's start, k >= 1 from Halton point k", "", {}});
  }
  for (std::size_t s = 0; s < searches.size(); ++s) {
    const StudyResults& rows = searches[s];
    r.status.insert(r.status.end(), rows.status.begin(), rows.status.end());
    for (std::size_t k = 0; k < rows.parameters.size(); ++k) {
      auto& to = r.parameters[k].values;
      to.insert(to.end(), rows.parameters[k].values.begin(), rows.parameters[k].values.end());
    }
    for (std::size_t k = 0; k < rows.indicators.size(); ++k) {
      auto& to = r.indicators[k].values;
      to.insert(to.end(), rows.indicators[k].values.begin(), rows.indicators[k].values.end());
    }
    if (several) r.parameters.back().values.resize(r.status.size(), static_cast<double>(s));
  }
  for (std::size_t row = 0; row < r.status.size(); ++row) {
    r.dimensions[0].values.push_back(static_cast<double>(row));
  }
  const std::vector<double>& objective = r.find_column("objective")->values;
  const std::vector<double>& feasible = r.find_column("feasible")->values;
  std::optional<std::size_t> best;
  for (std::size_t row = 0; row < r.status.size(); ++row) {
    if (feasible[row] == 1.0 && (!best || objective[row] < objective[*best])) best = row;
  }
  if (best) {
    r.numeric_attributes.emplace_back("best_evaluation", static_cast<double>(*best));
    r.numeric_attributes.emplace_back("best_objective", objective[*best]);
    for (const ResultColumn& c : r.parameters) {
      r.numeric_attributes.emplace_back("best_" + c.name, c.values[*best]);
    }
    for (const ResultColumn& c : r.indicators) {
      if (c.name != "objective" && c.name != "feasible") {
        r.numeric_attributes.emplace_back("best_" + c.name, c.values[*best]);
      }
    }
  }
  r.text_attributes.emplace_back("algorithm", plan.optimize.algorithm);
  return r;
}

// The searches of one optimisation while they run: the finished ones' outcomes, the running
// ones' rows, the counts for progress; checkpoints of the table as it stands. Every member
// function may be called from any thread.
class Optimization {
 public:
  Optimization(const Plan& plan, const OptimizeOptions& options)
      : plan_(plan),
        options_(options),
        previous_(rows_by_start(plan, options.previous)),
        running_(previous_.size(), nullptr),
        finished_(previous_.size()),
        last_checkpoint_(std::chrono::steady_clock::now()) {}

  std::span<const StudyResults> previous() const { return previous_; }

  /// An evaluation of a search running here.
  void evaluated(bool ok, bool feasible, double objective) {
    {
      std::lock_guard lock(mutex_);
      ++evaluations_;
      count(ok, feasible, objective);
    }
    report();
  }

  void started(long start, const Search* search) {
    std::lock_guard lock(mutex_);
    running_[static_cast<std::size_t>(start)] = search;
  }

  /// A search's end. `counted`: whether its evaluations went through evaluated().
  void finished(long start, SearchOutcome outcome, bool counted) {
    {
      std::lock_guard lock(mutex_);
      const auto s = static_cast<std::size_t>(start);
      if (!counted) {
        const StudyResults& r = outcome.rows;
        const std::vector<double>& objective = r.find_column("objective")->values;
        const std::vector<double>& feasible = r.find_column("feasible")->values;
        for (std::size_t row = 0; row < r.status.size(); ++row) {
          ++evaluations_;
          count(r.status[row] == 0, feasible[row] == 1.0, objective[row]);
        }
      }
      running_[s] = nullptr;
      finished_[s] = std::move(outcome);
    }
    report();
  }

  OptimizeOutcome outcome() {
    OptimizeOutcome out;
    std::vector<StudyResults> rows;
    std::string termination;
    for (std::size_t s = 0; s < finished_.size(); ++s) {
      if (!finished_[s]) {  // never run (a stop): the previous run's rows stay
        finished_[s] = SearchOutcome{previous_[s], "NOT_RUN", 0, 0, true};
      }
      SearchOutcome& search = *finished_[s];
      out.computed += search.computed;
      out.reused += search.reused;
      out.interrupted = out.interrupted || search.interrupted;
      termination += finished_.size() == 1 ? search.termination
                                           : (s ? "; start " : "start ") + std::to_string(s) +
                                                 ": " + search.termination;
      rows.push_back(std::move(search.rows));
    }
    out.results = evaluations_table(plan_, rows);
    out.results.text_attributes.emplace_back("termination", termination);
    out.unstable = std::count_if(out.results.status.begin(), out.results.status.end(),
                                 [](int status) { return status != 0; });
    const auto best =
        std::find_if(out.results.numeric_attributes.begin(), out.results.numeric_attributes.end(),
                     [](const auto& attribute) { return attribute.first == "best_evaluation"; });
    if (best != out.results.numeric_attributes.end()) out.best = std::lround(best->second);
    out.termination = std::move(termination);
    return out;
  }

  /// The table as it stands: a finished search's rows, a running one's so far, and for a
  /// search not started (or not caught up with them) the previous run's rows.
  StudyResults snapshot() const {
    std::vector<StudyResults> rows(previous_.size());
    std::lock_guard lock(mutex_);
    for (std::size_t s = 0; s < rows.size(); ++s) {
      rows[s] = finished_[s]  ? finished_[s]->rows
                : running_[s] ? running_[s]->rows()
                              : previous_[s];
    }
    StudyResults table = evaluations_table(plan_, rows);
    table.text_attributes.emplace_back("termination", "checkpoint");
    return table;
  }

 private:
  void count(bool ok, bool feasible, double objective) {
    if (!ok) ++unstable_;
    if (feasible && !(objective >= best_objective_)) best_objective_ = objective;
  }

  // Progress after every evaluation, a checkpoint every checkpoint_seconds: one thread at a
  // time, the others go on.
  void report() {
    std::unique_lock reporting(reporting_, std::try_to_lock);
    if (!reporting.owns_lock()) return;
    long evaluations = 0, unstable = 0;
    double best = kNaN;
    {
      std::lock_guard lock(mutex_);
      evaluations = evaluations_;
      unstable = unstable_;
      best = best_objective_;
    }
    if (options_.progress) {
      options_.progress(evaluations, plan_.optimize.starts * plan_.optimize.max_evaluations,
                        unstable, best);
    }
    if (options_.checkpoint &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_)
                .count() >= options_.checkpoint_seconds) {
      options_.checkpoint(snapshot());
      last_checkpoint_ = std::chrono::steady_clock::now();
    }
  }

  const Plan& plan_;
  const OptimizeOptions& options_;
  const std::vector<StudyResults> previous_;
  mutable std::mutex mutex_;  // guards everything below
  std::vector<const Search*> running_;
  std::vector<std::optional<SearchOutcome>> finished_;
  long evaluations_ = 0, unstable_ = 0;
  double best_objective_ = kNaN;
  std::mutex reporting_;
  std::chrono::steady_clock::time_point last_checkpoint_;
};

}  // namespace

std::vector<double> start_point(const OptimizeStudy& study, long start) {
  std::vector<double> x;
  for (std::size_t k = 0; k < study.parameters.size(); ++k) {
    const OptimizeParameter& p = study.parameters[k];
    x.push_back(start == 0 ? p.initial()
                           : p.lower + (p.upper - p.lower) * radical_inverse(start, nth_prime(k)));
  }
  return x;
}

StudyResults empty_search_rows(const Plan& plan) {
  StudyResults r;
  r.plan_name = plan.name;
  r.plan_text = plan.text;
  r.study_kind = to_string(plan.kind);
  r.method = to_string(plan.base.method.kind);
  r.dimensions.push_back({"evaluation", "1", {}});
  const auto add_parameter_column = [&](const std::string& name) {
    const ParameterInfo* info = find_parameter(name);
    r.parameters.push_back(
        {name, info && *info->unit ? info->unit : "1", info ? info->description : name, "", {}});
  };
  for (const OptimizeParameter& p : plan.optimize.parameters) add_parameter_column(p.name);
  for (const char* derived : {"beta", "gamma"}) {
    if (!r.find_column(derived)) add_parameter_column(derived);
  }
  // Every indicator is stored: the objective and constraints are recomputed from them on
  // resume.
  for (const IndicatorInfo& info : indicator_table()) {
    r.indicators.push_back({info.name, info.units, info.name, info.definition, {}});
  }
  r.indicators.push_back(
      {"objective", "1", "objective", "sum of weight * indicator; kPenalty = 1e10 if not ok", {}});
  r.indicators.push_back(
      {"feasible", "1", "feasible", "1 if ok and every constraint holds, else 0", {}});
  return r;
}

SearchOutcome run_search(const Plan& plan, long start, const StudyResults* previous,
                         const std::atomic<bool>* stop) {
  Search search(plan, previous, stop, {});
  std::string termination = run_nlopt(plan, start, search);
  return search.outcome(std::move(termination));
}

OptimizeOutcome run_optimization(const Plan& plan, const OptimizeOptions& options) {
  Optimization optimization(plan, options);
  std::vector<long> starts(static_cast<std::size_t>(plan.optimize.starts));
  std::iota(starts.begin(), starts.end(), 0L);
  if (options.searches) {
    try {
      options.searches(plan, starts, optimization.previous(), options.stop,
                       [&](long start, SearchOutcome outcome) {
                         optimization.finished(start, std::move(outcome), false);
                       });
    } catch (const std::exception& e) {
      if (options.checkpoint) options.checkpoint(optimization.snapshot());  // keep what ended
      throw std::runtime_error(std::string(e.what()) +
                               " (every search that ended is saved; fix the cause and continue "
                               "with --resume)");
    }
  } else {
    const auto count = static_cast<long>(starts.size());
    FirstFailure failure;  // a failed checkpoint inside a search: rethrown after the region
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, options.threads))
    for (long s = 0; s < count; ++s) {
      failure.run([&] {
        Search search(plan, &optimization.previous()[static_cast<std::size_t>(s)], options.stop,
                      [&](bool ok, bool feasible, double objective) {
                        optimization.evaluated(ok, feasible, objective);
                      });
        optimization.started(s, &search);
        std::string termination = run_nlopt(plan, s, search);
        optimization.finished(s, search.outcome(std::move(termination)), true);
      });
    }
    failure.rethrow_if_failed();
  }
  return optimization.outcome();
}

}  // namespace impactid
