// Expansion of grid and list plans into points: counts, the partitions convention, row-major
// order, coupled values and what each point's settings hold.
#include "study/plan/point_set.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "study/plan/plan.hpp"

namespace impactid {
namespace {

Plan plan_of(const std::string& text) {
  try {
    return parse_plan(text, "test.toml");
  } catch (const PlanError& e) {
    ADD_FAILURE() << e.what();
    throw;
  }
}

Simulation built(const SimulationSettings& settings) {
  auto result = build(settings);
  if (auto* e = std::get_if<ParameterError>(&result)) {
    ADD_FAILURE() << e->field << " = " << e->value << ": " << e->constraint;
    return {};
  }
  return std::get<Simulation>(result);
}

std::string grid_over_length(double from, double to, long partitions) {
  return "[study]\nkind = \"grid\"\n[study.axes]\nlength = { from = " + format_value(from) +
         ", to = " + format_value(to) + ", partitions = " + std::to_string(partitions) + " }\n";
}

TEST(PointSet, KPartitionsGiveKPlusOneValuesWithExactEnds) {
  for (const long k : {1L, 2L, 3L, 7L, 40L, 999L}) {
    SCOPED_TRACE("partitions = " + std::to_string(k));
    const Plan plan = plan_of(grid_over_length(0.1, 0.7, k));
    const PointSet points(plan);
    ASSERT_EQ(points.size(), k + 1);
    ASSERT_EQ(points.dimension_values().size(), 1u);
    const std::vector<double>& v = points.dimension_values()[0];
    ASSERT_EQ(v.size(), static_cast<std::size_t>(k + 1));
    EXPECT_EQ(v.front(), 0.1);  // exactly as written, not 0.1 + 0*step rounded
    EXPECT_EQ(v.back(), 0.7);   // exactly as written, not 0.1 + k*step rounded
    for (long i = 1; i < k; ++i) {
      EXPECT_EQ(v[static_cast<std::size_t>(i)], 0.1 + static_cast<double>(i) * (0.7 - 0.1) / k);
    }
    for (std::size_t i = 1; i < v.size(); ++i) EXPECT_LT(v[i - 1], v[i]);
    EXPECT_EQ(points.shape(), (std::vector<long>{k + 1}));
  }
}

TEST(PointSet, UnitIntervalValuesAreCorrectlyRoundedFractions) {
  // from + i*(to - from)/k multiplies before dividing: over [0, 1] every value is the double
  // nearest i/k, so δ = 0.075 is stored as 0.075, not as 3*0.025 = 0.07500000000000001.
  const Plan plan = plan_of(
      "[method]\nname = \"newmark\"\n[study]\nkind = \"grid\"\n[study.axes]\n"
      "delta = { from = 0, to = 1, partitions = 40 }\n");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 41);
  for (long i = 0; i <= 40; ++i) {
    EXPECT_EQ(points.dimension_values()[0][static_cast<std::size_t>(i)], i / 40.0) << i;
    EXPECT_EQ(points.parameter_values(i), (std::vector<double>{i / 40.0}));
  }
  EXPECT_EQ(points.dimension_values()[0][3], 0.075);
}

TEST(PointSet, DescendingRangeRunsFromFromToTo) {
  const Plan plan = plan_of(grid_over_length(30.0, 10.0, 4));
  const PointSet points(plan);
  EXPECT_EQ(points.dimension_values()[0], (std::vector<double>{30.0, 25.0, 20.0, 15.0, 10.0}));
}

TEST(PointSet, GridIsRowMajorWithTheLastAxisFastest) {
  const std::vector<double> alphas{-0.5, -0.4, -0.3};
  const std::vector<double> deltas{0.4, 0.5, 0.6, 0.7};
  const Plan plan = plan_of(R"([scene]
elements = 40
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { values = [-0.5, -0.4, -0.3] }
delta = { values = [0.4, 0.5, 0.6, 0.7] }
)");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 12);
  EXPECT_EQ(points.shape(), (std::vector<long>{3, 4}));
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"alpha", "delta"}));
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"alpha", "delta"}));
  EXPECT_EQ(points.dimension_values(), (std::vector<std::vector<double>>{alphas, deltas}));
  for (long k = 0; k < 12; ++k) {
    SCOPED_TRACE("flat index " + std::to_string(k));
    const auto a = static_cast<std::size_t>(k / 4), d = static_cast<std::size_t>(k % 4);
    EXPECT_EQ(points.grid_indices(k), (std::vector<long>{k / 4, k % 4}));
    EXPECT_EQ(points.parameter_values(k), (std::vector<double>{alphas[a], deltas[d]}));
    const SimulationSettings s = points.settings(k);
    EXPECT_EQ(s.method.kind, MethodKind::hht);
    EXPECT_EQ(s.method.given.number("alpha"), alphas[a]);
    EXPECT_EQ(s.method.given.number("delta"), deltas[d]);
    EXPECT_EQ(s.scene.elements, 40);  // the base is kept
    const Simulation sim = built(s);
    EXPECT_EQ(numeric_value(sim, "alpha"), alphas[a]);
    EXPECT_EQ(numeric_value(sim, "delta"), deltas[d]);
  }
}

TEST(PointSet, AxesKeepFileOrderNotKeyOrder) {
  const Plan plan = plan_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
delta = { values = [0.4, 0.5] }
alpha = { values = [-0.3, -0.2, -0.1] }
)");
  const PointSet points(plan);
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"delta", "alpha"}));
  EXPECT_EQ(points.shape(), (std::vector<long>{2, 3}));
  EXPECT_EQ(points.parameter_values(1), (std::vector<double>{0.4, -0.2}));
  EXPECT_EQ(points.parameter_values(3), (std::vector<double>{0.5, -0.3}));
}

TEST(PointSet, CoupledAxisIsComputedAtEveryPoint) {
  const Plan plan = plan_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0.0, partitions = 50 }
delta = "-1.5*alpha"
)");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 51);
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"alpha"}));
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"alpha", "delta"}));
  for (long k = 0; k <= 50; ++k) {
    SCOPED_TRACE("flat index " + std::to_string(k));
    const double alpha = k == 50 ? 0.0 : -0.5 + static_cast<double>(k) * 0.5 / 50;
    const std::vector<double> v = points.parameter_values(k);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[0], alpha);
    EXPECT_EQ(v[1], -1.5 * alpha);
    const SimulationSettings s = points.settings(k);
    EXPECT_EQ(s.method.given.number("alpha"), alpha);
    EXPECT_EQ(s.method.given.number("delta"), -1.5 * alpha);
  }
  EXPECT_EQ(points.parameter_values(0)[1], 0.75);
  EXPECT_EQ(points.parameter_values(50)[1], 0.0);
}

TEST(PointSet, CoupledAxisMayUseSeveralAxes) {
  const Plan plan = plan_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
courant = { values = [0.5, 1.0] }
alpha = { values = [-0.3, -0.1] }
delta = "courant*0.5 - alpha"
)");
  const PointSet points(plan);
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"courant", "alpha", "delta"}));
  EXPECT_EQ(points.parameter_values(0), (std::vector<double>{0.5, -0.3, 0.25 + 0.3}));
  EXPECT_EQ(points.parameter_values(1), (std::vector<double>{0.5, -0.1, 0.25 + 0.1}));
  EXPECT_EQ(points.parameter_values(2), (std::vector<double>{1.0, -0.3, 0.5 + 0.3}));
  EXPECT_EQ(points.parameter_values(3), (std::vector<double>{1.0, -0.1, 0.5 + 0.1}));
  EXPECT_EQ(points.settings(2).scene.courant, 1.0);
  EXPECT_TRUE(points.settings(2).courant_given);
}

TEST(PointSet, ListPointsApplyTheirKeysOverTheBase) {
  const std::string text = R"([scene]
elements = 60
[method]
name = "newmark"
delta = 0.2
[study]
kind = "list"
points = [
  { delta = 0.0, courant = 0.25 },
  { mass = "consistent", delta = 0.3 },
  { courant = 0.8 },
]
)";
  const Plan plan = plan_of(text);
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 3);
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"point"}));
  EXPECT_EQ(points.dimension_values(), (std::vector<std::vector<double>>{{0.0, 1.0, 2.0}}));
  EXPECT_EQ(points.shape(), (std::vector<long>{3}));
  // Numeric keys only (mass is applied but not a numeric parameter), in order of appearance.
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"delta", "courant"}));

  EXPECT_EQ(points.parameter_values(0), (std::vector<double>{0.0, 0.25}));
  // Point 1 leaves courant out: the value in effect is the default 0.5 (through dt, so to
  // rounding).
  const std::vector<double> v1 = points.parameter_values(1);
  EXPECT_EQ(v1[0], 0.3);
  EXPECT_DOUBLE_EQ(v1[1], 0.5);
  // Point 2 leaves delta out: the base's 0.2.
  EXPECT_EQ(points.parameter_values(2)[0], 0.2);
  EXPECT_EQ(points.parameter_values(2)[1], 0.8);

  const SimulationSettings s0 = points.settings(0), s1 = points.settings(1),
                           s2 = points.settings(2);
  EXPECT_EQ(s0.method.given.number("delta"), 0.0);
  EXPECT_EQ(s0.scene.courant, 0.25);
  EXPECT_EQ(s0.scene.mass, MassMatrix::lumped);
  EXPECT_EQ(s1.scene.mass, MassMatrix::consistent);
  EXPECT_EQ(s1.scene.courant, 0.5);
  EXPECT_FALSE(s1.courant_given);
  EXPECT_EQ(s2.method.given.number("delta"), 0.2);
  for (const auto* s : {&s0, &s1, &s2}) {
    EXPECT_EQ(s->scene.elements, 60);
    EXPECT_EQ(s->method.kind, MethodKind::newmark);
    built(*s);
  }
}

TEST(PointSet, ListValueIsNanWhereThePointsMethodHasNoSuchParameter) {
  const Plan plan = plan_of(R"([method]
name = "newmark"
[study]
kind = "list"
[[study.points]]
delta = 0.4
[[study.points]]
method = "cdm"
)");
  const PointSet points(plan);
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"delta"}));
  EXPECT_EQ(points.parameter_values(0), (std::vector<double>{0.4}));
  EXPECT_TRUE(std::isnan(points.parameter_values(1)[0]));
  EXPECT_EQ(points.settings(1).method.kind, MethodKind::central_difference);
}

TEST(PointSet, ApplyReportsWhatAssignRejects) {
  // A plan put together by hand, bypassing load_plan()'s checks.
  Plan plan;
  plan.kind = StudyKind::grid;
  plan.axes = {{"elements", {10.0, 20.5}}};
  const PointSet points(plan);
  SimulationSettings s;
  EXPECT_FALSE(points.apply(0, s));
  EXPECT_EQ(s.scene.elements, 10);
  s = SimulationSettings{};
  const auto error = points.apply(1, s);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->field, "elements");
  EXPECT_EQ(error->constraint, "must be an integer below 2e9");
}

}  // namespace
}  // namespace impactid
