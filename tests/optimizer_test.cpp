// NLopt searches, cross-checked against a grid over the same parameter.
#include "study/studies/optimizer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

#include "study/plan/plan.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

std::string plan_text(const std::string& algorithm, long budget, const std::string& extra = "") {
  return R"(
name = "optimizer-test"
[scene]
elements = 40
[method]
name = "newmark"
[study]
kind = "optimize"
algorithm = ")" + algorithm + R"("
objective = "eps_p"
max_evaluations = )" + std::to_string(budget) + R"(
xtol_rel = 1e-6
[study.parameters]
delta = { from = 0.1, to = 1.0 }
)" + extra;
}

double eps_p_at(double delta) {
  SimulationSettings s;
  s.scene.elements = 40;
  s.method.kind = MethodKind::newmark;
  s.method.given.set("delta", delta);
  SimulationWorkspace workspace;
  return evaluate(std::get<Simulation>(build(s)), workspace).indicators.eps_p;
}

struct GridMinimum {
  double delta, eps_p;
};

// The reference: a fine grid over the same interval.
GridMinimum grid_minimum(double step) {
  GridMinimum best{NAN, std::numeric_limits<double>::infinity()};
  for (double d = 0.1; d <= 1.0 + 1e-12; d += step) {
    const double e = eps_p_at(d);
    if (e < best.eps_p) best = {d, e};
  }
  return best;
}

double best_attribute(const OptimizeOutcome& o, const std::string& name) {
  for (const auto& [key, value] : o.results.numeric_attributes) {
    if (key == name) return value;
  }
  ADD_FAILURE() << name << " missing";
  return NAN;
}

TEST(Optimizer, DirectFindsTheGridMinimumOfNewmarkDelta) {
  const GridMinimum grid = grid_minimum(0.01);
  const Plan plan = parse_plan(plan_text("DIRECT", 120), "optimizer-test.toml");
  const OptimizeOutcome o = run_optimization(plan, {});
  ASSERT_TRUE(o.best.has_value()) << o.termination;
  const double delta = best_attribute(o, "best_delta");
  const double eps_p = best_attribute(o, "best_objective");
  // As good as the grid's best (up to the grid's resolution), and close to its location.
  EXPECT_LE(eps_p, grid.eps_p * (1.0 + 1e-3));
  EXPECT_NEAR(delta, grid.delta, 0.02);
  EXPECT_DOUBLE_EQ(eps_p, eps_p_at(delta));  // the reported best is what simulate gives there
  EXPECT_EQ(o.results.points_total(), o.computed);  // every evaluation is recorded
}

TEST(Optimizer, ConstraintHoldsAtTheBestPoint) {
  // NoP_p falls with δ: requiring few peaks pushes the optimum to larger δ than the
  // unconstrained one, and the best point must satisfy it.
  const Plan plan = parse_plan(plan_text("COBYLA", 80, "[study.constraints]\nnop_p = { max = 6 }\n"),
                               "optimizer-test.toml");
  const OptimizeOutcome o = run_optimization(plan, {});
  ASSERT_TRUE(o.best.has_value()) << o.termination;
  EXPECT_LE(best_attribute(o, "best_nop_p"), 6.0);
  const ResultColumn* feasible = o.results.find_column("feasible");
  ASSERT_NE(feasible, nullptr);
  EXPECT_EQ(feasible->values[static_cast<std::size_t>(*o.best)], 1.0);
}

TEST(Optimizer, NonNativeConstraintsGoThroughAuglag) {
  const Plan plan = parse_plan(
      plan_text("NELDERMEAD", 80, "[study.constraints]\nnop_p = { max = 6 }\n"), "o.toml");
  const OptimizeOutcome o = run_optimization(plan, {});
  ASSERT_TRUE(o.best.has_value()) << o.termination;
  EXPECT_LE(best_attribute(o, "best_nop_p"), 6.0);
  EXPECT_LE(o.results.points_total(), 80);
}

TEST(Optimizer, ResumeReplaysRecordedEvaluations) {
  const Plan plan = parse_plan(plan_text("COBYLA", 12), "optimizer-test.toml");
  const OptimizeOutcome full = run_optimization(plan, {});
  ASSERT_EQ(full.results.points_total(), 12);

  // A first run stopped after 5 evaluations, then resumed from its table.
  std::atomic<bool> stop{false};
  OptimizeOptions first_options;
  first_options.progress = [&](long done, long, long, double) {
    if (done >= 5) stop.store(true);
  };
  first_options.stop = &stop;
  const OptimizeOutcome first = run_optimization(plan, first_options);
  EXPECT_TRUE(first.interrupted);
  EXPECT_EQ(first.results.points_total(), 5);

  OptimizeOptions resume_options;
  resume_options.previous = &first.results;
  const OptimizeOutcome resumed = run_optimization(plan, resume_options);
  EXPECT_EQ(resumed.reused, 5);
  EXPECT_EQ(resumed.computed, 7);
  // Every column, the status and the best point equal the uninterrupted run's, bit for bit
  // (NaN where it is NaN): replaying a row must restore every indicator, not a chosen few.
  const auto same_bits = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  };
  EXPECT_EQ(full.results.status, resumed.results.status);
  for (const auto* columns : {&full.results.parameters, &full.results.indicators}) {
    for (const ResultColumn& a : *columns) {
      if (a.name == "wall_time_s") continue;  // a measurement, not a result
      const ResultColumn* b = resumed.results.find_column(a.name);
      ASSERT_TRUE(b) << a.name;
      EXPECT_TRUE(same_bits(a.values, b->values)) << a.name;
    }
  }
  ASSERT_EQ(full.results.numeric_attributes.size(), resumed.results.numeric_attributes.size());
  for (std::size_t k = 0; k < full.results.numeric_attributes.size(); ++k) {
    const auto& [name, value] = full.results.numeric_attributes[k];
    if (name.find("wall_time") != std::string::npos) continue;
    EXPECT_EQ(resumed.results.numeric_attributes[k].first, name);
    EXPECT_TRUE(same_bits({value}, {resumed.results.numeric_attributes[k].second})) << name;
  }
}

// --- several searches (`starts`) ---------------------------------------------------------------

const ResultColumn& column(const StudyResults& r, const std::string& name) {
  const ResultColumn* c = r.find_column(name);
  if (!c) throw std::runtime_error("no column " + name);
  return *c;
}

bool same_bits(const std::vector<double>& x, const std::vector<double>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}

// Every column but the measured run time, bit for bit.
void expect_same_table(const StudyResults& a, const StudyResults& b) {
  EXPECT_EQ(a.status, b.status);
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (const auto* columns : {&a.parameters, &a.indicators}) {
    for (const ResultColumn& x : *columns) {
      if (x.name == "wall_time_s") continue;
      EXPECT_TRUE(same_bits(x.values, column(b, x.name).values)) << x.name;
    }
  }
  ASSERT_EQ(a.numeric_attributes.size(), b.numeric_attributes.size());
  for (std::size_t k = 0; k < a.numeric_attributes.size(); ++k) {
    if (a.numeric_attributes[k].first.find("wall_time") != std::string::npos) continue;
    EXPECT_EQ(a.numeric_attributes[k].first, b.numeric_attributes[k].first);
    EXPECT_TRUE(same_bits({a.numeric_attributes[k].second}, {b.numeric_attributes[k].second}))
        << a.numeric_attributes[k].first;
  }
}

std::string two_parameter_plan(long starts, const std::string& start_text = "", unsigned seed = 1) {
  return R"(
name = "multi-start-test"
[scene]
elements = 40
[method]
name = "hht"
[study]
kind = "optimize"
algorithm = "COBYLA"
objective = "eps_p"
max_evaluations = 40
seed = )" +
         std::to_string(seed) + R"(
starts = )" +
         std::to_string(starts) + R"(
[study.parameters]
delta = { from = 0.0, to = 1.0)" +
         start_text + R"( }
alpha = { from = -0.5, to = 0.0 }
[study.constraints]
nop_p = { max = 15 }
)";
}

// Halton (1964): the radical inverses of k in bases 2 and 3, scaled to the bounds.
TEST(MultiStart, SearchKStartsAtTheKthHaltonPoint) {
  const Plan plan = parse_plan(two_parameter_plan(4), "multi-start-test.toml");
  const std::vector<std::vector<double>> unit{
      {0.5, 1.0 / 3.0}, {0.25, 2.0 / 3.0}, {0.75, 1.0 / 9.0}};
  for (long k = 1; k <= 3; ++k) {
    const std::vector<double> x = start_point(plan.optimize, k);
    ASSERT_EQ(x.size(), 2u);
    EXPECT_DOUBLE_EQ(x[0], unit[k - 1][0]) << k;
    EXPECT_DOUBLE_EQ(x[1], -0.5 + 0.5 * unit[k - 1][1]) << k;
  }
  // Search 0 starts where a one-search plan does: the middle of the bounds here.
  EXPECT_EQ(start_point(plan.optimize, 0), (std::vector<double>{0.5, -0.25}));
}

TEST(MultiStart, TheTableIsTheSameOnOneOrThreeThreads) {
  const Plan plan = parse_plan(two_parameter_plan(5), "multi-start-test.toml");
  OptimizeOptions one, three;
  one.threads = 1;
  three.threads = 3;
  const OptimizeOutcome a = run_optimization(plan, one);
  const OptimizeOutcome b = run_optimization(plan, three);
  EXPECT_EQ(a.computed, b.computed);
  expect_same_table(a.results, b.results);
  EXPECT_EQ(a.termination, b.termination);
}

// The cross-check: search k of a multi-start run is the plain optimisation (one search) started
// at search k's point with seed + k, evaluation for evaluation.
TEST(MultiStart, EachSearchIsThePlainOptimisationFromItsStartPoint) {
  const Plan plan = parse_plan(two_parameter_plan(4), "multi-start-test.toml");
  OptimizeOptions options;
  options.threads = 2;
  const OptimizeOutcome multi = run_optimization(plan, options);
  const std::vector<double>& start = column(multi.results, "start").values;
  for (long k = 0; k < 4; ++k) {
    SCOPED_TRACE("search " + std::to_string(k));
    const std::vector<double> x = start_point(plan.optimize, k);
    char delta[64], alpha[64];
    std::snprintf(delta, sizeof delta, ", start = %.17g", x[0]);
    std::snprintf(alpha, sizeof alpha, ", start = %.17g }", x[1]);
    std::string text = two_parameter_plan(1, delta, 1 + static_cast<unsigned>(k));
    const std::string old_alpha = "alpha = { from = -0.5, to = 0.0 }";
    text.replace(text.find(old_alpha), old_alpha.size(),
                 "alpha = { from = -0.5, to = 0.0" + std::string(alpha));
    const OptimizeOutcome single = run_optimization(parse_plan(text, "single.toml"), {});
    std::vector<std::size_t> rows;
    for (std::size_t r = 0; r < start.size(); ++r) {
      if (start[r] == static_cast<double>(k)) rows.push_back(r);
    }
    ASSERT_EQ(rows.size(), single.results.status.size());
    for (const char* name : {"delta", "alpha", "eps_p", "eps_v", "nop_p", "objective"}) {
      const std::vector<double>& a = column(multi.results, name).values;
      const std::vector<double>& b = column(single.results, name).values;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_TRUE(same_bits({a[rows[i]]}, {b[i]})) << name << " row " << i;
      }
    }
  }
}

TEST(MultiStart, TheBestIsTheFirstLeastFeasibleObjectiveOfAllSearches) {
  const Plan plan = parse_plan(two_parameter_plan(4), "multi-start-test.toml");
  const OptimizeOutcome o = run_optimization(plan, {});
  const std::vector<double>& objective = column(o.results, "objective").values;
  const std::vector<double>& feasible = column(o.results, "feasible").values;
  std::optional<std::size_t> best;
  for (std::size_t r = 0; r < objective.size(); ++r) {
    if (feasible[r] == 1.0 && (!best || objective[r] < objective[*best])) best = r;
  }
  ASSERT_TRUE(best && o.best);
  EXPECT_EQ(static_cast<std::size_t>(*o.best), *best);
  EXPECT_EQ(best_attribute(o, "best_objective"), objective[*best]);
  EXPECT_EQ(best_attribute(o, "best_start"), column(o.results, "start").values[*best]);
  // Search 0 alone is the plain optimisation: the best of four is at least as good.
  const OptimizeOutcome plain =
      run_optimization(parse_plan(two_parameter_plan(1), "multi-start-test.toml"), {});
  ASSERT_TRUE(plain.best);
  EXPECT_LE(objective[*best], best_attribute(plain, "best_objective"));
}

TEST(MultiStart, AStoppedRunResumesToTheSameTable) {
  const Plan plan = parse_plan(two_parameter_plan(4), "multi-start-test.toml");
  OptimizeOptions full_options;
  full_options.threads = 2;
  const OptimizeOutcome full = run_optimization(plan, full_options);

  std::atomic<bool> stop{false};
  std::optional<StudyResults> saved;
  OptimizeOptions first;
  first.threads = 2;
  first.stop = &stop;
  first.checkpoint_seconds = 0.0;
  first.checkpoint = [&](const StudyResults& r) { saved = r; };
  first.progress = [&](long done, long, long, double) {
    if (done >= 50) stop.store(true);
  };
  const OptimizeOutcome stopped = run_optimization(plan, first);
  EXPECT_TRUE(stopped.interrupted);
  ASSERT_LT(stopped.results.points_total(), full.results.points_total());

  ASSERT_TRUE(saved);
  for (const StudyResults* from : {&stopped.results, static_cast<const StudyResults*>(&*saved)}) {
    OptimizeOptions resume;
    resume.threads = 2;
    resume.previous = from;
    const OptimizeOutcome resumed = run_optimization(plan, resume);
    EXPECT_FALSE(resumed.interrupted);
    EXPECT_EQ(resumed.reused, from->points_total());
    expect_same_table(full.results, resumed.results);
  }
}

}  // namespace
}  // namespace impactid
