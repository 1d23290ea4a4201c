// NLopt searches, cross-checked against a grid over the same parameter.
#include "study/studies/optimizer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

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

}  // namespace
}  // namespace impactid
