#include "study/studies/optimizer.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <nlopt.hpp>

#include "metrics/indicator_table.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool supports_inequality_constraints(nlopt::algorithm a) {
  return a == nlopt::LN_COBYLA || a == nlopt::GN_ISRES || a == nlopt::GN_ORIG_DIRECT ||
         a == nlopt::GN_ORIG_DIRECT_L;
}

// The optimisation in progress: NLopt's callbacks land here.
class Problem {
 public:
  Problem(const Plan& plan, const OptimizeOptions& options) : plan_(plan), options_(options) {
    const OptimizeStudy& study = plan.optimize;
    results_.plan_name = plan.name;
    results_.plan_text = plan.text;
    results_.study_kind = to_string(plan.kind);
    results_.method = to_string(plan.base.method.kind);
    results_.dimensions.push_back({"evaluation", "1", {}});
    for (const OptimizeParameter& p : study.parameters) add_parameter_column(p.name);
    for (const char* derived : {"beta", "gamma"}) {
      if (!find_column(derived)) add_parameter_column(derived);
    }
    // Every indicator is stored: the objective and constraints are recomputed from them on
    // resume.
    for (const IndicatorInfo& info : indicator_table()) {
      results_.indicators.push_back({info.name, info.units, info.name, info.definition, {}});
    }
    results_.indicators.push_back({"objective",
                                   "1",
                                   "objective",
                                   "sum of weight * indicator; kPenalty = 1e10 if not ok",
                                   {}});
    results_.indicators.push_back(
        {"feasible", "1", "feasible", "1 if ok and every constraint holds, else 0", {}});
    last_checkpoint_ = std::chrono::steady_clock::now();
  }

  // Evaluates x (or replays it), records it, and returns its index in the table.
  std::size_t evaluate_at(const double* x) {
    const std::size_t n = plan_.optimize.parameters.size();
    if (last_ && std::equal(x, x + n, last_x_.begin())) return *last_;
    if (options_.stop && options_.stop->load()) {
      interrupted_ = true;
      throw nlopt::forced_stop();
    }
    if (static_cast<long>(results_.status.size()) >= plan_.optimize.max_evaluations) {
      budget_exhausted_ = true;  // AUGLAG's subsidiary runs can overrun NLopt's own count
      throw nlopt::forced_stop();
    }
    last_x_.assign(x, x + n);
    const std::size_t row = results_.status.size();
    if (!replay(x, row)) compute(x, row);
    last_ = row;
    if (options_.progress) {
      options_.progress(static_cast<long>(row + 1), plan_.optimize.max_evaluations, unstable_,
                        best_objective_);
    }
    if (options_.checkpoint &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_)
                .count() >= options_.checkpoint_seconds) {
      options_.checkpoint(finished());
      last_checkpoint_ = std::chrono::steady_clock::now();
    }
    return row;
  }

  double objective(std::size_t row) const { return column("objective").values[row]; }
  double constraint(std::size_t row, std::size_t j) const { return violations_[row][j]; }

  StudyResults finished() const {
    StudyResults r = results_;
    if (best_) {
      r.numeric_attributes.emplace_back("best_evaluation", static_cast<double>(*best_));
      r.numeric_attributes.emplace_back("best_objective", best_objective_);
      for (const ResultColumn& c : r.parameters) {
        r.numeric_attributes.emplace_back("best_" + c.name, c.values[*best_]);
      }
      for (const ResultColumn& c : r.indicators) {
        if (c.name != "objective" && c.name != "feasible") {
          r.numeric_attributes.emplace_back("best_" + c.name, c.values[*best_]);
        }
      }
    }
    r.text_attributes.emplace_back("algorithm", plan_.optimize.algorithm);
    return r;
  }

  OptimizeOutcome outcome(std::string termination) const {
    OptimizeOutcome out;
    out.results = finished();
    out.results.text_attributes.emplace_back("termination", termination);
    out.computed = computed_;
    out.reused = reused_;
    out.unstable = unstable_;
    if (best_) out.best = static_cast<long>(*best_);
    out.termination = std::move(termination);
    out.interrupted = interrupted_;
    return out;
  }

 private:
  void add_parameter_column(const std::string& name) {
    const ParameterInfo* info = find_parameter(name);
    results_.parameters.push_back(
        {name, info && *info->unit ? info->unit : "1", info ? info->description : name, "", {}});
  }
  const ResultColumn* find_column(const std::string& name) const {
    return results_.find_column(name);
  }
  const ResultColumn& column(const std::string& name) const { return *find_column(name); }
  ResultColumn& column(const std::string& name) { return *results_.find_column(name); }

  // Re-uses the previous run's row `row` if it was computed at exactly this x.
  bool replay(const double* x, std::size_t row) {
    const StudyResults* prev = options_.previous;
    if (!prev || diverged_ || row >= prev->status.size()) return false;
    for (std::size_t k = 0; k < plan_.optimize.parameters.size(); ++k) {
      const ResultColumn* c = prev->find_column(plan_.optimize.parameters[k].name);
      if (!c || c->values[row] != x[k]) {
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
    std::vector<std::pair<std::string, double>> params;
    for (const ResultColumn& c : results_.parameters)
      params.emplace_back(c.name, get(c.name.c_str()));
    record(e, params);
    ++reused_;
    return true;
  }

  void compute(const double* x, std::size_t) {
    SimulationSettings settings = plan_.base;
    for (std::size_t k = 0; k < plan_.optimize.parameters.size(); ++k) {
      assign(settings, plan_.optimize.parameters[k].name, x[k]);
    }
    auto built = build(settings);
    std::vector<std::pair<std::string, double>> params;
    Evaluation e;
    if (auto* sim = std::get_if<Simulation>(&built)) {
      e = evaluate(*sim, workspace_);
      for (const ResultColumn& c : results_.parameters) {
        params.emplace_back(c.name, numeric_value(*sim, c.name).value_or(kNaN));
      }
    } else {
      // NLopt stays inside the bounds that load_plan() checked, so this is a defect.
      e.summary.status = RunStatus::failed;
      e.indicators = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
      for (const ResultColumn& c : results_.parameters) params.emplace_back(c.name, kNaN);
    }
    record(e, params);
    ++computed_;
  }

  void record(const Evaluation& e, const std::vector<std::pair<std::string, double>>& params) {
    const std::size_t row = results_.status.size();
    results_.status.push_back(static_cast<int>(e.summary.status));
    results_.dimensions[0].values.push_back(static_cast<double>(row));
    for (std::size_t k = 0; k < params.size(); ++k) {
      results_.parameters[k].values.push_back(params[k].second);
    }
    for (const IndicatorInfo& info : indicator_table()) {
      column(info.name).values.push_back(info.value(e));
    }
    const bool ok = e.summary.status == RunStatus::ok;
    if (!ok) ++unstable_;
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
    column("objective").values.push_back(objective);
    column("feasible").values.push_back(feasible ? 1.0 : 0.0);
    if (feasible && (!best_ || objective < best_objective_)) {
      best_ = row;
      best_objective_ = objective;
    }
  }

  const Plan& plan_;
  const OptimizeOptions& options_;
  StudyResults results_;
  std::vector<std::vector<double>> violations_;
  SimulationWorkspace workspace_;
  std::optional<std::size_t> last_, best_;
  std::vector<double> last_x_;
  double best_objective_ = kNaN;
  long computed_ = 0, reused_ = 0, unstable_ = 0;
  bool diverged_ = false, interrupted_ = false;

 public:
  bool budget_exhausted_ = false;
  std::chrono::steady_clock::time_point last_checkpoint_;
};

struct ConstraintData {
  Problem* problem;
  std::size_t index;
};

double objective_callback(unsigned, const double* x, double*, void* data) {
  auto* problem = static_cast<Problem*>(data);
  return problem->objective(problem->evaluate_at(x));
}

double constraint_callback(unsigned, const double* x, double*, void* data) {
  auto* c = static_cast<ConstraintData*>(data);
  return c->problem->constraint(c->problem->evaluate_at(x), c->index);
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

}  // namespace

OptimizeOutcome run_optimization(const Plan& plan, const OptimizeOptions& options) {
  const OptimizeStudy& study = plan.optimize;
  const auto n = static_cast<unsigned>(study.parameters.size());
  const nlopt::algorithm algorithm =
      static_cast<nlopt::algorithm>(nlopt_algorithm_from_string(study.algorithm.c_str()));

  Problem problem(plan, options);
  std::vector<double> lower, upper, x;
  for (const OptimizeParameter& p : study.parameters) {
    lower.push_back(p.lower);
    upper.push_back(p.upper);
    x.push_back(p.initial());
  }

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
  nlopt::srand(study.seed);
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_min_objective(objective_callback, &problem);
  std::vector<ConstraintData> constraint_data;
  constraint_data.reserve(constraint_count);
  for (std::size_t j = 0; j < constraint_count; ++j) {
    constraint_data.push_back({&problem, j});
    opt.add_inequality_constraint(constraint_callback, &constraint_data.back(), 0.0);
  }
  opt.set_maxeval(static_cast<int>(study.max_evaluations));
  opt.set_xtol_rel(study.xtol_rel);
  if (study.ftol_rel > 0) opt.set_ftol_rel(study.ftol_rel);

  std::string termination;
  try {
    double f = 0.0;
    termination = result_name(opt.optimize(x, f));
  } catch (const nlopt::forced_stop&) {
    termination = problem.budget_exhausted_ ? "MAXEVAL_REACHED" : "FORCED_STOP";
  } catch (const nlopt::roundoff_limited&) {
    termination = "ROUNDOFF_LIMITED";
  } catch (const std::exception& e) {
    termination = std::string("FAILURE: ") + e.what();
  }
  return problem.outcome(termination);
}

}  // namespace impactid
