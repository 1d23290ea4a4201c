// Plan files: what a valid plan of each kind parses to, and that every kind of mistake is
// reported as "file:line:column: key = value: what" at the place it is written.
#include "study/plan/plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/reference/exact_solution.hpp"
#include "core/reference/scene_reference.hpp"
#include "core/run/simulation.hpp"
#include "metrics/indicator_table.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

Plan plan_of(const std::string& text) {
  try {
    return parse_plan(text, "plans/test.toml");
  } catch (const PlanError& e) {
    ADD_FAILURE() << e.what();
    throw;
  }
}

// The message parse_plan() throws for `text`, or a test failure.
std::string error_of(const std::string& text) {
  try {
    parse_plan(text, "bad.toml");
  } catch (const PlanError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the plan was accepted:\n" << text;
  return "";
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

#define EXPECT_STARTS_WITH(text, prefix) EXPECT_PRED2(starts_with, text, prefix)

std::vector<std::string> all_indicators() {
  std::vector<std::string> out;
  for (const IndicatorInfo& info : indicator_table()) out.push_back(info.name);
  return out;
}

// ---- valid plans ----------------------------------------------------------------------------

TEST(Plan, GridPlanParsesToItsContent) {
  const std::string text = R"(name = "fig3"
description = "Newmark over delta"
[scene]
elements = 50
length = 20
[method]
name = "newmark"
[study]
kind = "grid"
[study.axes]
delta = { from = 0.0, to = 1.0, partitions = 4 }
courant = { values = [1, 0.5] }
)";
  const Plan plan = plan_of(text);
  EXPECT_EQ(plan.name, "fig3");
  EXPECT_EQ(plan.description, "Newmark over delta");
  EXPECT_EQ(plan.text, text);
  EXPECT_EQ(plan.path, std::filesystem::path("plans/test.toml"));
  EXPECT_EQ(plan.kind, StudyKind::grid);
  EXPECT_EQ(plan.base.scene.elements, 50);
  EXPECT_EQ(plan.base.scene.length, 20.0);  // a TOML integer where a real is expected
  EXPECT_EQ(plan.base.method.kind, MethodKind::newmark);
  EXPECT_FALSE(plan.base.method.given.has("delta"));  // an axis, not a base value
  ASSERT_EQ(plan.axes.size(), 2u);
  EXPECT_EQ(plan.axes[0].name, "delta");  // file order, although "courant" sorts first
  EXPECT_EQ(plan.axes[0].values, (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(plan.axes[1].name, "courant");
  EXPECT_EQ(plan.axes[1].values, (std::vector<double>{1.0, 0.5}));
  EXPECT_TRUE(plan.coupled.empty());
  EXPECT_EQ(plan.output.file, std::filesystem::path("results/fig3.h5"));
  EXPECT_EQ(plan.output.indicators, all_indicators());
  EXPECT_EQ(plan.output.checkpoint_seconds, 10.0);
}

TEST(Plan, NameDefaultsToTheFileStem) {
  const Plan plan =
      plan_of("[study]\nkind = \"grid\"\n[study.axes]\nalpha = { values = [-0.1] }\n");
  EXPECT_EQ(plan.name, "test");
  EXPECT_EQ(plan.description, "");
  EXPECT_EQ(plan.output.file, std::filesystem::path("results/test.h5"));
  EXPECT_EQ(plan.base.method.kind, MethodKind::hht);  // the table's default method
}

TEST(Plan, CoupledAxisIsParsed) {
  const Plan plan = plan_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 10 }
delta = "-1.5*alpha"
)");
  ASSERT_EQ(plan.axes.size(), 1u);
  EXPECT_EQ(plan.axes[0].name, "alpha");
  ASSERT_EQ(plan.coupled.size(), 1u);
  EXPECT_EQ(plan.coupled[0].name, "delta");
  EXPECT_EQ(plan.coupled[0].expression.text(), "-1.5*alpha");
  EXPECT_EQ(plan.coupled[0].expression.variables(), (std::vector<std::string>{"alpha"}));
}

TEST(Plan, ListPlanParsesInlineAndTableArrays) {
  const Plan inline_points = plan_of(R"([method]
name = "newmark"
[study]
kind = "list"
points = [
  { delta = 0.3, courant = 0.5 },
  { mass = "consistent", elements = 80 },
]
)");
  const Plan table_points = plan_of(R"([method]
name = "newmark"
[study]
kind = "list"
[[study.points]]
delta = 0.3
courant = 0.5
[[study.points]]
mass = "consistent"
elements = 80
)");
  for (const Plan* plan : {&inline_points, &table_points}) {
    EXPECT_EQ(plan->kind, StudyKind::list);
    ASSERT_EQ(plan->points.size(), 2u);
    const ListPoint first{{"delta", 0.3}, {"courant", 0.5}};
    const ListPoint second{{"mass", std::string("consistent")}, {"elements", 80.0}};
    EXPECT_EQ(plan->points[0], first);  // keys in file order
    EXPECT_EQ(plan->points[1], second);
  }
}

TEST(Plan, OptimizePlanParsesToItsContent) {
  const Plan plan = plan_of(R"(name = "opt"
[method]
name = "hht"
[study]
kind = "optimize"
algorithm = "NELDER-MEAD"
objective = { eps_p = 1.0, nop_p = 0.01 }
max_evaluations = 80
xtol_rel = 1e-3
ftol_rel = 0
seed = 7
[study.parameters]
delta = { from = 0, to = 1, start = 0.6 }
alpha = { from = -0.5, to = 0.0 }
[study.constraints]
nop_p = { max = 15 }
eps_v = { min = 0.001, max = 0.5 }
)");
  EXPECT_EQ(plan.kind, StudyKind::optimize);
  const OptimizeStudy& o = plan.optimize;
  EXPECT_EQ(o.algorithm, "LN_NELDERMEAD");
  const std::vector<std::pair<std::string, double>> objective{{"eps_p", 1.0}, {"nop_p", 0.01}};
  EXPECT_EQ(o.objective, objective);
  EXPECT_EQ(o.max_evaluations, 80);
  EXPECT_EQ(o.xtol_rel, 1e-3);
  EXPECT_EQ(o.ftol_rel, 0.0);
  EXPECT_EQ(o.seed, 7u);
  ASSERT_EQ(o.parameters.size(), 2u);
  EXPECT_EQ(o.parameters[0].name, "delta");
  EXPECT_EQ(o.parameters[0].lower, 0.0);
  EXPECT_EQ(o.parameters[0].upper, 1.0);
  EXPECT_EQ(o.parameters[0].start, 0.6);
  EXPECT_EQ(o.parameters[1].name, "alpha");
  EXPECT_EQ(o.parameters[1].lower, -0.5);
  EXPECT_EQ(o.parameters[1].upper, 0.0);
  EXPECT_FALSE(o.parameters[1].start);
  ASSERT_EQ(o.constraints.size(), 2u);
  EXPECT_EQ(o.constraints[0].indicator, "nop_p");
  EXPECT_EQ(o.constraints[0].max, 15.0);
  EXPECT_FALSE(o.constraints[0].min);
  EXPECT_EQ(o.constraints[1].indicator, "eps_v");
  EXPECT_EQ(o.constraints[1].min, 0.001);
  EXPECT_EQ(o.constraints[1].max, 0.5);
}

TEST(Plan, OptimizeDefaultsAndShortNames) {
  const std::string head = "[method]\nname = \"hht\"\n[study]\nkind = \"optimize\"\n";
  const std::string params = "[study.parameters]\nalpha = { from = -0.5, to = 0 }\n";
  const Plan defaults = plan_of(head + params);
  EXPECT_EQ(defaults.optimize.algorithm, "LN_COBYLA");
  const std::vector<std::pair<std::string, double>> eps_p{{"eps_p", 1.0}};
  EXPECT_EQ(defaults.optimize.objective, eps_p);
  EXPECT_EQ(defaults.optimize.max_evaluations, 200);
  EXPECT_EQ(defaults.optimize.starts, 1);
  EXPECT_TRUE(defaults.optimize.constraints.empty());

  const std::vector<std::pair<std::string, std::string>> names{
      {"DIRECT", "GN_DIRECT_L"},
      {"CRS2", "GN_CRS2_LM"},
      {"ISRES", "GN_ISRES"},
      {"COBYLA", "LN_COBYLA"},
      {"BOBYQA", "LN_BOBYQA"},
      {"NELDERMEAD", "LN_NELDERMEAD"},
      {"SBPLX", "LN_SBPLX"},
      {"GN_DIRECT", "GN_DIRECT"},
      {"GN_ORIG_DIRECT_L", "GN_ORIG_DIRECT_L"},
      {"GN_ESCH", "GN_ESCH"},
      {"LN_PRAXIS", "LN_PRAXIS"},
  };
  for (const auto& [given, stored] : names) {
    const Plan plan =
        plan_of(head + "algorithm = \"" + given + "\"\nobjective = \"nop_v\"\n" + params);
    EXPECT_EQ(plan.optimize.algorithm, stored) << given;
    const std::vector<std::pair<std::string, double>> nop_v{{"nop_v", 1.0}};
    EXPECT_EQ(plan.optimize.objective, nop_v);
  }
}

TEST(Plan, OutputSectionIsRead) {
  const Plan plan = plan_of(R"([study]
kind = "grid"
[study.axes]
alpha = { values = [-0.1] }
[output]
file = "/tmp/x/out.h5"
indicators = ["nop_p", "eps_p"]
checkpoint_seconds = 2
peak_prominence = 1e-4
energy_growth_limit = 3
)");
  EXPECT_EQ(plan.output.file, std::filesystem::path("/tmp/x/out.h5"));
  EXPECT_EQ(plan.output.indicators, (std::vector<std::string>{"nop_p", "eps_p"}));
  EXPECT_EQ(plan.output.checkpoint_seconds, 2.0);
  EXPECT_EQ(plan.base.indicators.peak_prominence, 1e-4);
  EXPECT_EQ(plan.base.run.energy_growth_limit, 3.0);
}

TEST(Plan, SceneAndMethodKeysReachTheBase) {
  const Plan plan = plan_of(R"([scene]
length = 10.5
elements = 30
youngs_modulus = 200000
density = 7.8e-9
area = 2
velocity = -500
gap = 0
mass = "consistent"
rayleigh_mass = 1
rayleigh_stiffness = 1e-8
dt = 1e-7
t_end = 1e-4
[method]
name = "generalized-alpha"
rho_inf = 0.5
hht_contact = "weighted"
[study]
kind = "list"
points = [{}]
)");
  const SimulationSettings& s = plan.base;
  EXPECT_EQ(s.scene.length, 10.5);
  EXPECT_EQ(s.scene.elements, 30);
  EXPECT_EQ(s.scene.youngs_modulus, 200000.0);
  EXPECT_EQ(s.scene.density, 7.8e-9);
  EXPECT_EQ(s.scene.area, 2.0);
  EXPECT_EQ(s.scene.velocity, -500.0);
  EXPECT_EQ(s.scene.gap, 0.0);
  EXPECT_EQ(s.scene.mass, MassMatrix::consistent);
  EXPECT_EQ(s.scene.rayleigh_mass, 1.0);
  EXPECT_EQ(s.scene.rayleigh_stiffness, 1e-8);
  EXPECT_EQ(s.scene.dt, 1e-7);
  EXPECT_EQ(s.scene.t_end, 1e-4);
  EXPECT_EQ(s.method.kind, MethodKind::generalized_alpha);
  EXPECT_EQ(s.method.given.number("rho_inf"), 0.5);
  EXPECT_EQ(s.method.given.choice("hht_contact"), "weighted");
}

// ---- errors: the exact place, key and value -------------------------------------------------

TEST(PlanErrors, TomlSyntaxError) {
  // Line 3 holds the unterminated array's next element, which TOML cannot read as a value.
  EXPECT_EQ(error_of("[scene]\nlength = [1,\nelements = 2\n"),
            "bad.toml:3:1: Error while parsing value: could not determine value type");
  EXPECT_STARTS_WITH(error_of("[scene]\nlength = 1\nlength = 2\n"), "bad.toml:3:");
}

// A table header nested 30,000 levels deep (issue 38: a 60 KB file overflowed the stack while
// its error message was built) is refused where the nesting passes the bound; 32 levels pass.
TEST(PlanErrors, TablesNestedTooDeep) {
  std::string deep = "[a";
  for (int i = 0; i < 30000; ++i) deep += ".a";
  EXPECT_EQ(error_of(deep + "]\n"),
            "bad.toml:1:1: tables and arrays nested more than 32 levels deep (a plan, scene or "
            "model file needs a few)");
  std::string arrays = "x = ";
  for (int i = 0; i < 40; ++i) arrays += "[";
  for (int i = 0; i < 40; ++i) arrays += "]";
  EXPECT_STARTS_WITH(error_of(arrays + "\n"), "bad.toml:1:");
  std::string allowed = "[a";
  for (int i = 1; i < 32; ++i) allowed += ".a";
  // 32 tables below the root: the reader's own message (an unknown key), not the bound.
  const std::string message = error_of(allowed + "]\n");
  EXPECT_STARTS_WITH(message, "bad.toml:1:1: a = { a = {");
  EXPECT_NE(message.find(": unknown key (top-level keys:"), std::string::npos) << message;
}

TEST(PlanErrors, UnknownKeys) {
  EXPECT_EQ(error_of("[scene]\nelements = 50\nbogus = 1\n"),
            "bad.toml:3:9: scene.bogus = 1: unknown key (scene keys: length, elements, "
            "youngs_modulus, density, area, velocity, gap, far_gap, mass, contact, "
            "penalty_stiffness, penalty_factor, "
            "augmented_tolerance, augmented_max_iterations, restitution, rayleigh_mass, "
            "rayleigh_stiffness, courant, dt, t_end)");
  EXPECT_EQ(error_of("nmae = \"x\"\n"),
            "bad.toml:1:8: nmae = \"x\": unknown key (top-level keys: name, description, scene, "
            "method, study, output)");
  EXPECT_EQ(error_of("[method]\nname = \"hht\"\nrho = 0.8\n"),
            "bad.toml:3:7: method.rho = 0.8: unknown key (method keys: name, delta, alpha, beta, "
            "gamma, rho_inf, substep_ratio, theta, p, cdm_velocity, hht_contact)");
  // A scene parameter is not a method key.
  EXPECT_STARTS_WITH(error_of("[method]\nelements = 3\n"),
                     "bad.toml:2:12: method.elements = 3: unknown key (method keys: name,");
  EXPECT_STARTS_WITH(
      error_of("[output]\nfiel = \"a.h5\"\n"),
      "bad.toml:2:8: output.fiel = \"a.h5\": unknown key (output keys: file, "
      "indicators, checkpoint_seconds, histories, peak_prominence, reference_tolerance, "
      "reference_method, reference_max_refinements, energy_growth_limit, verdict_eps_p, "
      "verdict_nop_p, verdict_eps_v, verdict_nop_v)");
  EXPECT_EQ(error_of("[study]\nkind = \"grid\"\nbogus = 2\n"),
            "bad.toml:3:9: study.bogus = 2: unknown key (grid keys: kind, axes, practical)");
  EXPECT_EQ(error_of("[study]\nkind = \"grid\"\n[study.axes]\n"
                     "alpha = { from = -0.5, to = 0, partitions = 4, step = 1 }\n"),
            "bad.toml:4:55: study.axes.alpha.step = 1: unknown key (axis keys: from, to, "
            "partitions, values)");
}

TEST(PlanErrors, WrongTypes) {
  EXPECT_EQ(error_of("[scene]\nelements = \"fifty\"\n"),
            "bad.toml:2:12: scene.elements = \"fifty\": must be a number");
  EXPECT_EQ(error_of("[scene]\nelements = 2.5\n"),
            "bad.toml:2:12: scene.elements = 2.5: must be an integer below 2e9");
  EXPECT_EQ(error_of("[scene]\nmass = true\n"),
            "bad.toml:2:8: scene.mass = true: must be a string, one of "
            "lumped|consistent|redistributed|singular");
  EXPECT_EQ(error_of("[scene]\nmass = 'heavy'\n"),
            "bad.toml:2:8: scene.mass = 'heavy': must be one of "
            "lumped|consistent|redistributed|singular");
  EXPECT_EQ(error_of("[method]\nname = \"rk4\"\n"),
            "bad.toml:2:8: method.name = \"rk4\": must be one of "
            "cdm|backward-euler|newmark|hht|generalized-alpha|bathe|rho-bathe|tr-bdf2|houbolt|"
            "wilson-theta|noh-bathe|kim-explicit|kr-alpha");
  EXPECT_EQ(error_of("scene = 3\n"),
            "bad.toml:1:9: scene = 3: must be a table ([scene]) or the name of a scene file");
  EXPECT_EQ(error_of("name = 3\n"), "bad.toml:1:8: name = 3: must be a string");
  EXPECT_EQ(error_of("[study]\nkind = \"sweep\"\n"),
            "bad.toml:2:8: study.kind = \"sweep\": must be \"grid\", \"list\", \"optimize\", "
            "\"spectral\" or \"work-precision\"");
  EXPECT_EQ(error_of("[study]\nkind = \"grid\"\n[study.axes]\nalpha = 3\n"),
            "bad.toml:4:9: study.axes.alpha = 3: must be { from = .., to = .., partitions = .. }, "
            "{ values = [..] } or a coupled-axis expression such as \"-1.5*alpha\"");
  EXPECT_EQ(error_of("[study]\nkind = \"grid\"\n[study.axes]\n"
                     "alpha = { from = -0.5, to = 0, partitions = 2.0 }\n"),
            "bad.toml:4:45: study.axes.alpha.partitions = 2.0: must be an integer");
  EXPECT_EQ(error_of("[output]\ncheckpoint_seconds = \"10\"\n"),
            "bad.toml:2:22: output.checkpoint_seconds = \"10\": must be a number");
}

TEST(PlanErrors, ValuesOutOfRangeNameTheirKey) {
  // From build(): the ParameterError's field is mapped back to where it is written.
  EXPECT_EQ(error_of(R"([method]
name = "hht"
alpha = -0.7
[study]
kind = "grid"
[study.axes]
delta = { from = 0, to = 1, partitions = 2 }
)"),
            "bad.toml:3:9: method.alpha = -0.7: must lie in [-0.5, 0]");
  EXPECT_EQ(error_of("[scene]\nlength = -2.0\n[study]\nkind = \"grid\"\n[study.axes]\n"
                     "alpha = { values = [-0.1] }\n"),
            "bad.toml:2:10: scene.length = -2.0: must be positive and finite");
  EXPECT_EQ(error_of("[output]\nenergy_growth_limit = 0.5\n[study]\nkind = \"grid\"\n"
                     "[study.axes]\nalpha = { values = [-0.1] }\n"),
            "bad.toml:2:23: output.energy_growth_limit = 0.5: must be > 1");
  EXPECT_EQ(error_of("[output]\ncheckpoint_seconds = 0\n"),
            "bad.toml:2:22: output.checkpoint_seconds = 0: must be > 0");
  // A rule across two keys is reported at the second one in the file.
  EXPECT_EQ(error_of("[scene]\ncourant = 0.5\ndt = 1e-7\n"),
            "bad.toml:3:6: scene.dt = 1e-7: cannot be given with courant");
}

TEST(PlanErrors, ParameterTheMethodDoesNotTake) {
  EXPECT_EQ(error_of(R"([method]
name = "cdm"
delta = 0.3
[study]
kind = "grid"
[study.axes]
courant = { values = [0.5, 1] }
)"),
            "bad.toml:3:9: method.delta = 0.3: is not a parameter of method cdm (it applies to "
            "newmark|hht)");
  // The same parameter as an axis is reported at the axis, with the first point.
  EXPECT_EQ(error_of(R"([method]
name = "cdm"
[study]
kind = "grid"
[study.axes]
delta = { values = [0.5, 1] }
)"),
            "bad.toml:6:9: study.axes.delta = 0.5: is not a parameter of method cdm (it applies "
            "to newmark|hht) (at grid point 0: delta = 0.5)");
}

TEST(PlanErrors, BadAxisExpression) {
  EXPECT_EQ(error_of(R"([study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 5 }
delta = "-1.5*"
)"),
            "bad.toml:5:9: study.axes.delta = \"-1.5*\": invalid expression: column 6: expected a "
            "number, a name or '(' but found the end");
  EXPECT_EQ(error_of(R"([study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 5 }
delta = "alpha^2"
)"),
            "bad.toml:5:9: study.axes.delta = \"alpha^2\": invalid expression: column 6: "
            "expected an operator (+ - * /) or the end but found '^' (powers are not supported)");
}

TEST(PlanErrors, CoupledAxisNames) {
  EXPECT_EQ(error_of(R"([study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 5 }
delta = "-1.5*beta"
)"),
            "bad.toml:5:9: study.axes.delta = \"-1.5*beta\": uses 'beta', which is not an axis "
            "(independent axes: alpha)");
  EXPECT_EQ(error_of(R"([study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 5 }
delta = "-1.5*gamma"
gamma = "2*alpha"
)"),
            "bad.toml:5:9: study.axes.delta = \"-1.5*gamma\": uses 'gamma', a coupled axis: an "
            "expression may use only independent axes (alpha)");
  EXPECT_EQ(error_of("[study]\nkind = \"grid\"\n[study.axes]\ndelta = \"0.5\"\n"),
            "bad.toml:3:1: study.axes = { delta = \"0.5\" }: a grid needs at least one independent "
            "axis");
}

TEST(PlanErrors, GridPointOutOfRangeIsReportedAtItsAxis) {
  // alpha = -0.7 first appears at flat index 4 = (alpha 2, delta 0): row-major, delta fastest.
  EXPECT_EQ(error_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { values = [-0.5, -0.25, -0.7] }
delta = { values = [0.5, 1.0] }
)"),
            "bad.toml:6:9: study.axes.alpha = -0.7: must lie in [-0.5, 0] (at grid point 4: "
            "alpha = -0.7, delta = 0.5)");
  EXPECT_EQ(error_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = 0, to = -0.75, partitions = 3 }
)"),
            "bad.toml:6:9: study.axes.alpha = -0.75: must lie in [-0.5, 0] (at grid point 3: "
            "alpha = -0.75)");
  // kim-explicit's p: the key noh-bathe also takes, with its own range.
  EXPECT_EQ(error_of(R"([method]
name = "kim-explicit"
[study]
kind = "grid"
[study.axes]
p = { values = [0.4, 0.54] }
)"),
            "bad.toml:6:5: study.axes.p = 0.54: must lie in [1/3, 1/2] (1/3 written "
            "0.3333333333333333) for kim-explicit (below 1/3 it is unstable at every useful step; "
            "above 1/2 its stability limit falls and no contact multiplier keeps the step's end on "
            "the wall) (at grid point 1: p = 0.54)");
  // A coupled value out of range is reported at the coupled axis.
  EXPECT_EQ(error_of(R"([method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.5, to = 0, partitions = 4 }
delta = "3*alpha + 1"
)"),
            "bad.toml:7:9: study.axes.delta = -0.5: must be >= 0 and finite (eq. 13) (at grid "
            "point 0: alpha = -0.5, delta = -0.5)");
}

TEST(PlanErrors, ListPointErrors) {
  EXPECT_EQ(error_of(R"([method]
name = "newmark"
[study]
kind = "list"
points = [
  { delta = 0.3, courant = 0.5 },
  { mass = "consistent", delta = -1 },
]
)"),
            "bad.toml:7:34: study.points[1].delta = -1: must be >= 0 and finite (eq. 13) (at list "
            "point 1)");
  // A point that breaks a rule across parameters, with the missing one named at the point.
  EXPECT_EQ(error_of(R"([method]
name = "newmark"
beta = 0.25
[study]
kind = "list"
[[study.points]]
gamma = 0.5
[[study.points]]
courant = 1
)"),
            "bad.toml:8:1: study.points[1].gamma = (missing): must be given with beta (at list "
            "point 1)");
  EXPECT_EQ(error_of("[study]\nkind = \"list\"\npoints = [{ delta = 0.3 }, { bogus = 1 }]\n"),
            std::string("bad.toml:3:38: study.points[1].bogus = 1: unknown key (point keys are "
                        "parameters: ") +
                "length, elements, youngs_modulus, density, area, velocity, gap, far_gap, mass, "
                "contact, penalty_stiffness, penalty_factor, "
                "augmented_tolerance, augmented_max_iterations, restitution, "
                "rayleigh_mass, rayleigh_stiffness, courant, dt, t_end, method, delta, alpha, "
                "beta, gamma, rho_inf, substep_ratio, theta, p, cdm_velocity, hht_contact, "
                "peak_prominence, "
                "reference_tolerance, reference_method, reference_max_refinements, "
                "energy_growth_limit, verdict_eps_p, verdict_nop_p, verdict_eps_v, "
                "verdict_nop_v)");
  EXPECT_EQ(error_of("[study]\nkind = \"list\"\npoints = []\n"),
            "bad.toml:3:10: study.points = []: must hold at least one point");
  EXPECT_EQ(error_of("[study]\nkind = \"list\"\npoints = [{ elements = 2.5 }]\n"),
            "bad.toml:3:24: study.points[0].elements = 2.5: must be an integer below 2e9");
}

TEST(Plan, ChoiceAxisIsAGridDimensionOfItsWords) {
  const Plan plan = plan_of(R"(
[study]
kind = "grid"
[study.axes]
contact = { values = ["penalty", "lagrange"] }
penalty_factor = { values = [1.0, 10.0] }
)");
  ASSERT_EQ(plan.axes.size(), 2u);
  EXPECT_EQ(plan.axes[0].name, "contact");
  EXPECT_EQ(plan.axes[0].values, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(plan.axes[0].labels, (std::vector<std::string>{"penalty", "lagrange"}));
  EXPECT_TRUE(plan.axes[1].labels.empty());
  const PointSet points(plan);
  EXPECT_EQ(points.dimension_labels()[0], plan.axes[0].labels);
  // Point 1 (penalty, 10) and point 2 (lagrange, 1): the word and the number both applied.
  const SimulationSettings penalty = points.settings(1);
  EXPECT_EQ(penalty.run.contact.law, ContactLaw::penalty);
  EXPECT_EQ(penalty.run.contact.penalty_factor, 10.0);
  EXPECT_EQ(points.settings(2).run.contact.law, ContactLaw::lagrange);
  EXPECT_EQ(points.parameter_values(2), (std::vector<double>{1.0, 1.0}));
}

TEST(PlanErrors, ChoiceAxisRules) {
  const std::string head = "[study]\nkind = \"grid\"\n[study.axes]\n";
  EXPECT_EQ(error_of(head + "contact = { values = [\"lagrange\", \"springs\"] }\n"),
            "bad.toml:4:35: study.axes.contact.values[1] = \"springs\": must be one of "
            "lagrange|penalty|augmented-lagrangian|paoli-schatzman");
  EXPECT_EQ(error_of(head + "method = { values = [\"hht\", \"newmark\"] }\n"),
            "bad.toml:4:10: study.axes.method = { values = [\"hht\", \"newmark\"] }: is not an "
            "axis: compare methods in a list or a work-precision study");
  EXPECT_EQ(error_of(head + "contact = { values = [\"penalty\", \"penalty\"] }\n"),
            "bad.toml:4:34: study.axes.contact.values[1] = \"penalty\": repeats an earlier word");
  EXPECT_EQ(error_of(head + "contact = { values = [1] }\n"),
            "bad.toml:4:23: study.axes.contact.values[0] = 1: must be a word "
            "(lagrange|penalty|augmented-lagrangian|paoli-schatzman)");
  EXPECT_EQ(error_of(head + "contact = { from = 0, to = 2, partitions = 2 }\n"),
            "bad.toml:4:20: study.axes.contact.from = 0: unknown key (a choice axis has only: "
            "values)");
  EXPECT_EQ(error_of(head + "contact = \"penalty\"\n"),
            "bad.toml:4:11: study.axes.contact = \"penalty\": a choice axis is { values = "
            "[\"word\", ..] }");
  EXPECT_EQ(error_of(head + "contact = { values = [\"penalty\"] }\nalpha = { values = [-0.1] "
                            "}\ndelta = \"contact - alpha\"\n"),
            "bad.toml:6:9: study.axes.delta = \"contact - alpha\": uses 'contact', a choice axis: "
            "an expression may use only numeric axes (alpha)");
  EXPECT_EQ(error_of("[scene]\ncontact = \"penalty\"\n" + head +
                     "contact = { values = [\"lagrange\"] }\n"),
            "bad.toml:6:11: study.axes.contact = { values = [\"lagrange\"] }: is also set as "
            "scene.contact: a parameter is either fixed or a grid axis");
}

TEST(PlanErrors, GridAxisRules) {
  const std::string head = "[study]\nkind = \"grid\"\n[study.axes]\n";
  EXPECT_EQ(error_of("[method]\ndelta = 0.3\n" + head + "delta = { values = [0.1] }\n"),
            "bad.toml:6:9: study.axes.delta = { values = [0.1] }: is also set as method.delta: a "
            "parameter is either fixed or a grid axis");
  EXPECT_EQ(error_of(head + "mass = { values = [1] }\n"),
            "bad.toml:4:20: study.axes.mass.values[0] = 1: must be a word "
            "(lumped|consistent|redistributed|singular)");
  EXPECT_STARTS_WITH(error_of(head + "beta2 = { values = [1] }\n"),
                     "bad.toml:4:9: study.axes.beta2 = { values = [1] }: is not a parameter "
                     "(numeric parameters: length, elements,");
  EXPECT_EQ(error_of(head + "alpha = { from = -0.5, to = 0, partitions = 0 }\n"),
            "bad.toml:4:45: study.axes.alpha.partitions = 0: must be >= 1");
  EXPECT_EQ(error_of(head + "alpha = { from = -0.5, to = -0.5, partitions = 4 }\n"),
            "bad.toml:4:29: study.axes.alpha.to = -0.5: equals from; use values = [..] for a "
            "single value");
  EXPECT_EQ(error_of(head + "alpha = { from = -0.5, partitions = 4 }\n"),
            "bad.toml:4:9: study.axes.alpha.to = (missing): an axis needs from, to and "
            "partitions, or values");
  EXPECT_EQ(error_of(head + "alpha = { values = [] }\n"),
            "bad.toml:4:20: study.axes.alpha.values = []: must hold at least one value");
  EXPECT_EQ(error_of(head + "alpha = { values = [-0.1, -0.2, -0.1] }\n"),
            "bad.toml:4:33: study.axes.alpha.values[2] = -0.1: repeats an earlier value");
  EXPECT_EQ(error_of(head + "alpha = { values = [-0.1], from = 0 }\n"),
            "bad.toml:4:9: study.axes.alpha = { values = [-0.1], from = 0 }: give either values "
            "or from, to and partitions, not both");
  EXPECT_EQ(error_of(head + "elements = { from = 1, to = 2, partitions = 999999 }\n"
                            "length = { from = 1, to = 2, partitions = 1 }\n"),
            "bad.toml:3:1: study.axes = { elements = { from = 1, to = 2, partitions = 999999 }, "
            "length = { from = 1, ...: the grid has more than 1000000 points; split the study");
}

TEST(PlanErrors, OptimizeErrors) {
  const std::string head = "[method]\nname = \"hht\"\n[study]\nkind = \"optimize\"\n";
  EXPECT_STARTS_WITH(
      error_of(head +
               "algorithm = \"cobyla\"\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
      "bad.toml:5:13: study.algorithm = \"cobyla\": unknown algorithm (algorithms: GN_DIRECT, ");
  // A bound outside the parameter's range is reported at the bound.
  EXPECT_EQ(error_of(head + "[study.parameters]\nalpha = { from = -0.7, to = 0 }\n"),
            "bad.toml:6:18: study.parameters.alpha.from = -0.7: must lie in [-0.5, 0] (with alpha "
            "at its lower bound: alpha = -0.7)");
  EXPECT_EQ(error_of(head + "[study.parameters]\ndelta = { from = 0, to = 1 }\n"
                            "alpha = { from = -0.5, to = 0.25, start = -0.25 }\n"),
            "bad.toml:7:29: study.parameters.alpha.to = 0.25: must lie in [-0.5, 0] (with alpha at "
            "its upper bound: delta = 0.5, alpha = 0.25)");
  EXPECT_EQ(error_of("[method]\nname = \"cdm\"\n[study]\nkind = \"optimize\"\n"
                     "[study.parameters]\ndelta = { from = 0, to = 1 }\n"),
            "bad.toml:6:9: study.parameters.delta = { from = 0, to = 1 }: is not a parameter of "
            "method cdm (it applies to newmark|hht) (at the start point: delta = 0.5)");
  EXPECT_EQ(error_of(head + "[study.parameters]\nelements = { from = 10, to = 100 }\n"),
            "bad.toml:6:12: study.parameters.elements = { from = 10, to = 100 }: is an integer "
            "parameter: NLopt varies parameters continuously; vary it in a grid or list study");
  EXPECT_EQ(error_of(head + "[study.parameters]\nalpha = { from = 0, to = -0.5 }\n"),
            "bad.toml:6:26: study.parameters.alpha.to = -0.5: must be > from");
  EXPECT_EQ(error_of(head + "[study.parameters]\nalpha = { from = -0.5, to = 0, start = 1 }\n"),
            "bad.toml:6:40: study.parameters.alpha.start = 1: must lie in [from, to]");
  EXPECT_EQ(
      error_of(head + "max_evaluations = 0\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
      "bad.toml:5:19: study.max_evaluations = 0: must lie in [1, 2147483647]");
  EXPECT_EQ(error_of(head + "starts = 0\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
            "bad.toml:5:10: study.starts = 0: must lie in [1, 100000]");
  EXPECT_EQ(
      error_of(head + "starts = 100001\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
      "bad.toml:5:10: study.starts = 100001: must lie in [1, 100000]");
  EXPECT_EQ(error_of(head + "starts = 2.5\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
            "bad.toml:5:10: study.starts = 2.5: must be an integer");
  EXPECT_STARTS_WITH(
      error_of(head + "objective = \"eps\"\n[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"),
      "bad.toml:5:13: study.objective = \"eps\": unknown indicator (indicators: eps_p, eps_v,");
  EXPECT_EQ(error_of(head + "[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"
                            "[study.constraints]\nnop_p = { }\n"),
            "bad.toml:8:9: study.constraints.nop_p = { }: needs max, min or both");
  EXPECT_EQ(error_of(head + "[study.parameters]\nalpha = { from = -0.5, to = 0 }\n"
                            "[study.constraints]\nnop_p = { min = 5, max = 2 }\n"),
            "bad.toml:8:26: study.constraints.nop_p.max = 2: must be >= min");
  EXPECT_EQ(error_of(head),
            "bad.toml:3:1: study.parameters = (missing): an optimize study needs a table "
            "[study.parameters] of name = { from, to }");
}

TEST(PlanErrors, MissingStudy) {
  EXPECT_EQ(error_of("name = \"x\"\n"),
            "bad.toml:1:1: study = (missing): a plan needs a [study] table with kind = \"grid\", "
            "\"list\", \"optimize\", \"spectral\" or \"work-precision\"");
  EXPECT_EQ(error_of("[scene]\nelements = 10\n[study]\n"),
            "bad.toml:3:1: study.kind = (missing): must be \"grid\", \"list\", \"optimize\", "
            "\"spectral\" or \"work-precision\"");
}

TEST(PlanErrors, ColumnsCountCharactersNotBytes) {
  // "é" is two bytes; toml++ and the message count it as one column.
  EXPECT_EQ(error_of("description = \"é\"\n[scene]\n\"café\" = 1\n"),
            "bad.toml:3:10: scene.café = 1: unknown key (scene keys: length, elements, "
            "youngs_modulus, density, area, velocity, gap, far_gap, mass, contact, "
            "penalty_stiffness, penalty_factor, "
            "augmented_tolerance, augmented_max_iterations, restitution, rayleigh_mass, "
            "rayleigh_stiffness, courant, dt, t_end)");
}

TEST(PlanErrors, MissingFile) {
  try {
    load_plan("/nonexistent/plan.toml");
    ADD_FAILURE() << "no error";
  } catch (const PlanError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/plan.toml: cannot open the plan file");
  }
}

// ---- the shipped plans ----------------------------------------------------------------------

std::filesystem::path plans_dir() {
  return std::filesystem::path(IMPACTID_SOURCE_DIR) / "plans";
}

TEST(ShippedPlans, EveryPlanLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(plans_dir())) {
    if (entry.path().extension() != ".toml") continue;
    ++count;
    SCOPED_TRACE(entry.path().string());
    try {
      const Plan plan = load_plan(entry.path());
      EXPECT_EQ(plan.name, entry.path().stem().string());  // name = file name, by convention
      EXPECT_FALSE(plan.description.empty());
      EXPECT_EQ(plan.path, entry.path());
    } catch (const PlanError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GE(count, 6);
}

// plans/clamped-bar.toml is Doyen, Ern & Piperno's benchmark (L = E = ρ = 1, a = ½), so that its
// points are measured against the clamped bar's exact solution.
TEST(ShippedPlans, TheClampedBarIsTheBenchmark) {
  const Plan plan = load_plan(plans_dir() / "clamped-bar.toml");
  const auto built = build(plan.base);  // the scene that runs, whole-scene keys moved in
  ASSERT_TRUE(std::holds_alternative<Simulation>(built));
  const Scene* scene = std::get<Simulation>(built).bodies();
  ASSERT_NE(scene, nullptr);
  const std::optional<ClampedBarParams> bar = clamped_bar_params(*scene);
  ASSERT_TRUE(bar.has_value());
  EXPECT_EQ(bar->length, 1.0);
  EXPECT_EQ(bar->youngs_modulus, 1.0);
  EXPECT_EQ(bar->density, 1.0);
  EXPECT_EQ(bar->amplitude, 0.5);
  const PointSet points(plan);
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"alpha", "delta"}));
}

// plans/impacting-bar.toml is Siconos's ImpactingBar in SI units (m, kg, s): its 100 DOFs are
// 99 elements of 1 cm (l = L/nDof), E = 210e9 Pa, ρ = 7800 kg/m³, S = 3.14e-4 m², falling at
// 0.1 m/s from 5e-5 m, h = 2e-6 s, T = 1.5e-3 s, consistent mass. The rod's equations carry no
// units of their own, so its exact reference must come out in these: the numbers below are the
// closed forms evaluated from Siconos's values (c = √(E/ρ), 2L/c, ρcv0, ½ρSLv0²), not read
// from impactid.
TEST(ShippedPlans, TheImpactingBarIsSiconossSetUp) {
  const Plan plan = load_plan(plans_dir() / "impacting-bar.toml");
  const auto built = build(plan.base);
  ASSERT_TRUE(std::holds_alternative<Simulation>(built));
  const RodScene* rod = std::get<Simulation>(built).rod();
  ASSERT_NE(rod, nullptr);
  EXPECT_EQ(rod->elements, 99);  // nDof = 100 nodes
  EXPECT_EQ(rod->length, 0.99);  // 99 × l, l = L/nDof = 0.01
  EXPECT_EQ(rod->youngs_modulus, 210e9);
  EXPECT_EQ(rod->density, 7800.0);
  EXPECT_EQ(rod->area, 3.14e-4);
  EXPECT_EQ(rod->velocity, 0.1);  // toward the obstacle: Siconos's v0 = −0.1 along its axis
  EXPECT_EQ(rod->gap, 5e-5);
  EXPECT_EQ(rod->mass, MassMatrix::consistent);
  EXPECT_EQ(rod->dt, 2e-6);
  EXPECT_EQ(rod->t_end, 1.5e-3);
  EXPECT_FALSE(rod->far_gap.has_value());

  const RodSceneDerived d = derive(*rod);
  EXPECT_NEAR(d.element_length, 0.01, 1e-17);
  EXPECT_NEAR(d.wave_speed, 5188.745216627708, 1e-9);                   // √(210e9/7800) [m/s]
  EXPECT_NEAR(d.wave_speed * 2e-6 / 0.01, 1.0377490433255416, 1e-12);   // Siconos's Courant
  EXPECT_NEAR(d.impact_time, 5e-4, 1e-18);                              // gap/v0 [s]
  EXPECT_NEAR(d.contact_duration, 3.815951482171349e-4, 1e-16);         // 2L/c [s]
  EXPECT_NEAR(d.pressure_scale, 4047221.2689696127, 1e-6);              // ρcv0 [Pa]
  EXPECT_NEAR(d.pressure_scale * rod->area, 1270.8274784564583, 1e-9);  // the force [N]
  EXPECT_NEAR(d.initial_energy, 0.01212354, 1e-15);                     // ½ρSLv0² [J]
  EXPECT_EQ(d.step_count, 750);                                         // ⌈1.5e-3/2e-6⌉

  // The exact contact history in those units: flight, contact, release at 0.1 m/s.
  const RodImpactExact exact(*rod);
  EXPECT_NEAR(exact.release_time(), 8.81595148217135e-4, 1e-16);
  const ContactNodeValues before = exact.at(4e-4, 0.0);
  EXPECT_EQ(before.pressure, 0.0);
  EXPECT_EQ(before.velocity, 0.1);
  EXPECT_NEAR(before.displacement, 4e-5, 1e-19);
  const ContactNodeValues during = exact.at(7e-4, 0.0);
  EXPECT_NEAR(during.pressure, 4047221.2689696127, 1e-6);
  EXPECT_EQ(during.velocity, 0.0);
  EXPECT_EQ(during.displacement, 5e-5);
  const ContactNodeValues after = exact.at(1.2e-3, 0.0);
  EXPECT_EQ(after.pressure, 0.0);
  EXPECT_EQ(after.velocity, -0.1);
  EXPECT_NEAR(after.displacement, 5e-5 - 0.1 * (1.2e-3 - 8.81595148217135e-4), 1e-18);
  const ContactNodeValues landing = exact.at_sample(250);  // t = 5e-4, on the jump: the mean
  EXPECT_NEAR(landing.pressure, 0.5 * 4047221.2689696127, 1e-6);
  EXPECT_NEAR(landing.velocity, 0.05, 1e-15);
}

// Every point of plans/impacting-bar.toml runs against that reference. Measured when the plan was
// written: the trapezoidal rule chatters to the energy bound (`unstable`); every other point is
// ok with one or two contact episodes, ε_p from 0.0115 (KR-α) to 0.057 (backward Euler),
// p_max from 1.008 to 2.04 ρcv0, and keeps 0.80 to 0.99 of its energy.
TEST(ShippedPlans, TheImpactingBarRunsAgainstItsExactSolution) {
  const Plan plan = load_plan(plans_dir() / "impacting-bar.toml");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 12);
  SimulationWorkspace ws;
  for (long k = 0; k < points.size(); ++k) {
    const auto built = build(points.settings(k));
    ASSERT_TRUE(std::holds_alternative<Simulation>(built)) << k;
    const Evaluation e = evaluate(std::get<Simulation>(built), ws);
    if (k == 0) {  // newmark, δ = 0
      EXPECT_EQ(e.summary.status, RunStatus::unstable) << e.summary.message;
      continue;
    }
    ASSERT_EQ(e.summary.status, RunStatus::ok) << k << ": " << e.summary.message;
    EXPECT_EQ(e.summary.steps, 750) << k;
    EXPECT_GE(e.indicators.contact_episodes, 1.0) << k;
    EXPECT_LE(e.indicators.contact_episodes, 2.0) << k;
    EXPECT_LT(e.indicators.eps_p, 0.06) << k;
    EXPECT_LT(e.indicators.eps_v, 0.075) << k;
    EXPECT_GT(e.indicators.p_max_ratio, 1.0) << k;
    EXPECT_LT(e.indicators.p_max_ratio, 2.1) << k;
    EXPECT_GT(e.indicators.energy_ratio, 0.8) << k;
    EXPECT_LE(e.indicators.energy_ratio, 1.0) << k;
  }
}

TEST(ShippedPlans, PaperFiguresHaveThePapersGrids) {
  const Plan fig3 = load_plan(plans_dir() / "newmark-delta.toml");
  EXPECT_EQ(fig3.base.method.kind, MethodKind::newmark);
  ASSERT_EQ(fig3.axes.size(), 1u);
  EXPECT_EQ(fig3.axes[0].name, "delta");
  ASSERT_EQ(fig3.axes[0].values.size(), 41u);
  EXPECT_EQ(fig3.axes[0].values[1], 0.025);
  EXPECT_EQ(fig3.axes[0].values.back(), 1.0);
  EXPECT_EQ(fig3.base.scene.elements, 200);  // the paper's rod

  const Plan fig4 = load_plan(plans_dir() / "hht-delta-alpha.toml");
  EXPECT_EQ(fig4.base.method.kind, MethodKind::hht);
  const PointSet points(fig4);
  EXPECT_EQ(points.dimension_names(), (std::vector<std::string>{"alpha", "delta"}));
  EXPECT_EQ(points.shape(), (std::vector<long>{21, 41}));
  EXPECT_EQ(points.dimension_values()[0].front(), -0.5);
  EXPECT_EQ(points.dimension_values()[0].back(), 0.0);

  const Plan line = load_plan(plans_dir() / "hht-period-error-line.toml");
  ASSERT_EQ(line.coupled.size(), 1u);
  EXPECT_EQ(line.coupled[0].name, "delta");
  const PointSet line_points(line);
  for (long k = 0; k < line_points.size(); ++k) {
    const auto v = line_points.parameter_values(k);
    EXPECT_EQ(v[1], -1.5 * v[0]);  // eq. 19
  }

  const Plan opt = load_plan(plans_dir() / "hht-optimize.toml");
  EXPECT_EQ(opt.kind, StudyKind::optimize);
  EXPECT_EQ(opt.optimize.algorithm, "LN_COBYLA");
  ASSERT_EQ(opt.optimize.constraints.size(), 1u);
  EXPECT_EQ(opt.optimize.constraints[0].indicator, "nop_p");
  EXPECT_EQ(opt.optimize.constraints[0].max, 15.0);

  EXPECT_EQ(load_plan(plans_dir() / "list-methods.toml").kind, StudyKind::list);
  EXPECT_EQ(PointSet(load_plan(plans_dir() / "demo.toml")).size(), 11);
}

}  // namespace
}  // namespace impactid

namespace impactid {
namespace {

// [output] histories: a folder for grid and list studies, refused for an optimisation.
TEST(PlanOutput, HistoriesFolder) {
  const Plan plan = parse_plan(
      "[study]\nkind = \"list\"\npoints = [{ delta = 0.3 }]\n[method]\nname = \"newmark\"\n"
      "[output]\nhistories = \"results/h\"\n",
      "h.toml");
  ASSERT_TRUE(plan.output.histories.has_value());
  EXPECT_EQ(*plan.output.histories, "results/h");
  try {
    parse_plan(
        "[output]\nhistories = \"results/h\"\n[method]\nname = \"newmark\"\n[study]\n"
        "kind = \"optimize\"\n[study.parameters]\ndelta = { from = 0.1, to = 1.0 }\n",
        "o.toml");
    ADD_FAILURE() << "optimize with histories accepted";
  } catch (const PlanError& e) {
    EXPECT_NE(std::string(e.what()).find("o.toml:2:13: output.histories"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace impactid

namespace impactid {
namespace {

// ---- [study.practical] ----------------------------------------------------------------------

const char* kGridHead =
    "[method]\nname = \"newmark\"\n[study]\nkind = \"grid\"\n[study.axes]\n"
    "delta = { from = 0.0, to = 1.0, partitions = 4 }\n";

TEST(PlanPractical, ThresholdsOfGridAndListStudies) {
  const Plan grid = plan_of(std::string(kGridHead) +
                            "[study.practical]\neps_p = 0.03\nnop_p = { max = 15, min = 1 }\n"
                            "p_max_ratio = { min = 0.5 }\n");
  ASSERT_EQ(grid.practical.size(), 3u);
  EXPECT_EQ(grid.practical[0].indicator, "eps_p");  // file order
  EXPECT_EQ(grid.practical[0].max, 0.03);
  EXPECT_FALSE(grid.practical[0].min);
  EXPECT_EQ(grid.practical[1].indicator, "nop_p");
  EXPECT_EQ(grid.practical[1].max, 15.0);  // an integer where a number is expected
  EXPECT_EQ(grid.practical[1].min, 1.0);
  EXPECT_EQ(grid.practical[2].min, 0.5);
  EXPECT_FALSE(grid.practical[2].max);

  const Plan list = plan_of(
      "[study]\nkind = \"list\"\npoints = [{ method = \"cdm\" }]\npractical = { nop_p = 15 }\n");
  ASSERT_EQ(list.practical.size(), 1u);
  EXPECT_EQ(list.practical[0].max, 15.0);
  EXPECT_TRUE(plan_of(kGridHead).practical.empty());
}

TEST(PlanPractical, ErrorsAreLocated) {
  const std::string head = std::string(kGridHead) + "[study.practical]\n";  // line 7
  EXPECT_STARTS_WITH(error_of(head + "bogus = 1\n"),
                     "bad.toml:8:9: study.practical.bogus = 1: unknown indicator (indicators: "
                     "eps_p, eps_v, ");
  EXPECT_EQ(error_of(head + "eps_p = \"small\"\n"),
            "bad.toml:8:9: study.practical.eps_p = \"small\": must be a number (the largest "
            "practical value) or { max = .., min = .. }");
  EXPECT_EQ(error_of(head + "eps_p = -0.1\n"),
            "bad.toml:8:9: study.practical.eps_p = -0.1: must be >= 0 (indicators are never "
            "negative)");
  EXPECT_EQ(error_of(head + "eps_p = nan\n"),
            "bad.toml:8:9: study.practical.eps_p = nan: must be finite");
  EXPECT_EQ(error_of(head + "eps_p = { max = 0.1, min = 0.2 }\n"),
            "bad.toml:8:17: study.practical.eps_p.max = 0.1: must be >= min");
  EXPECT_EQ(error_of(head + "eps_p = { min = -1 }\n"),
            "bad.toml:8:17: study.practical.eps_p.min = -1: must be >= 0 (indicators are never "
            "negative)");
  EXPECT_EQ(error_of(head + "eps_p = { maximum = 1 }\n"),
            "bad.toml:8:21: study.practical.eps_p.maximum = 1: unknown key (threshold keys: "
            "max, min)");
  EXPECT_EQ(error_of(head + "eps_p = {}\n"),
            "bad.toml:8:9: study.practical.eps_p = {}: needs max, min or both");
  EXPECT_EQ(error_of(std::string(kGridHead) + "[study.practical]\n"),
            "bad.toml:7:1: study.practical = {}: must name at least one indicator");
  EXPECT_EQ(error_of(std::string(kGridHead) + "[study]\npractical = 3\n"),
            "bad.toml:7:1: Error while parsing table header: cannot redefine existing table "
            "'study'");
  EXPECT_EQ(error_of("[study]\nkind = \"list\"\npoints = [{ delta = 0.3 }]\npractical = 3\n"
                     "[method]\nname = \"newmark\"\n"),
            "bad.toml:4:13: study.practical = 3: must be a table of indicator = maximum, e.g. "
            "{ eps_p = 0.03, nop_p = 15 }");
  // Only stored indicators can be thresholds.
  EXPECT_EQ(error_of(head + "nop_p = 15\n[output]\nindicators = [\"eps_p\"]\n"),
            "bad.toml:8:9: study.practical.nop_p = 15: is not among [output] indicators (eps_p), "
            "so it is not stored");
  // Not for an optimisation: it has constraints.
  EXPECT_EQ(error_of("[method]\nname = \"newmark\"\n[study]\nkind = \"optimize\"\n"
                     "practical = { eps_p = 0.03 }\n[study.parameters]\n"
                     "delta = { from = 0.1, to = 1.0 }\n"),
            "bad.toml:5:13: study.practical = { eps_p = 0.03 }: is for grid and list studies; an "
            "optimisation states its limits as [study.constraints]");
}

// ---- kind = "spectral" ----------------------------------------------------------------------

const char* kSpectral = R"(name = "s"
[study]
kind = "spectral"
omega_dt = { from = 0.01, to = 100.0, points = 5 }
methods = [
  { method = "newmark", delta = 0.3 },
  { alpha = -0.3, method = "hht", delta = 0.45 },
  { method = "generalized-alpha", rho_inf = 0.8, hht_contact = "weighted" },
  { method = "cdm" },
]
alpha = { from = -0.5, to = 0.0, partitions = 2 }
delta = { values = [0.0, 0.5] }
omega_dt_reference = 2
stability_omega_max = 1.0e3
[output]
file = "out/s.h5"
)";

TEST(PlanSpectral, ParsesToItsContent) {
  const Plan plan = plan_of(kSpectral);
  EXPECT_EQ(plan.kind, StudyKind::spectral);
  EXPECT_STREQ(to_string(plan.kind), "spectral");
  const SpectralStudy& s = plan.spectral;
  ASSERT_EQ(s.omega_dt.size(), 5u);
  EXPECT_EQ(s.omega_dt.front(), 0.01);
  EXPECT_EQ(s.omega_dt.back(), 100.0);  // exactly as written
  EXPECT_NEAR(s.omega_dt[1], 0.1, 1e-15);
  EXPECT_NEAR(s.omega_dt[2], 1.0, 1e-15);
  ASSERT_EQ(s.methods.size(), 4u);
  EXPECT_EQ(s.methods[0].label, "newmark delta=0.3");
  EXPECT_EQ(s.methods[1].label, "hht alpha=-0.3 delta=0.45");  // the method first
  EXPECT_EQ(s.methods[2].label, "generalized-alpha rho_inf=0.8 hht_contact=weighted");
  EXPECT_EQ(s.methods[3].label, "cdm");
  const auto* hht = std::get_if<HhtParams>(&s.methods[1].params);
  ASSERT_NE(hht, nullptr);
  EXPECT_EQ(hht->alpha, -0.3);
  EXPECT_EQ(hht->delta, 0.45);
  EXPECT_EQ(kind_of(s.methods[3].params), MethodKind::central_difference);
  EXPECT_EQ(s.alpha, (std::vector<double>{-0.5, -0.25, 0.0}));
  EXPECT_EQ(s.delta, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(s.omega_dt_reference, 2.0);
  EXPECT_EQ(s.stability_omega_max, 1e3);
  EXPECT_EQ(plan.output.file, "out/s.h5");
}

TEST(PlanSpectral, Defaults) {
  const Plan plan = plan_of(
      "[study]\nkind = \"spectral\"\nomega_dt = { values = [1, 0.5] }\n"
      "methods = [{ method = \"hht\" }]\n");
  const SpectralStudy& s = plan.spectral;
  EXPECT_EQ(s.omega_dt, (std::vector<double>{1.0, 0.5}));
  EXPECT_EQ(s.alpha.size(), 21u);
  EXPECT_EQ(s.alpha.front(), -0.5);
  EXPECT_EQ(s.alpha.back(), 0.0);
  EXPECT_EQ(s.delta.size(), 41u);
  EXPECT_EQ(s.delta.back(), 1.0);
  EXPECT_EQ(s.omega_dt_reference, 1.0);
  EXPECT_EQ(s.stability_omega_max, 1e4);
  EXPECT_EQ(plan.output.file, "results/test.h5");
  EXPECT_EQ(s.methods[0].label, "hht");
}

TEST(PlanSpectral, ErrorsAreLocated) {
  const std::string head = "[study]\nkind = \"spectral\"\n";
  const std::string omega = "omega_dt = { values = [1] }\n";
  const std::string methods = "methods = [{ method = \"cdm\" }]\n";
  EXPECT_EQ(error_of(head + methods),
            "bad.toml:1:1: study.omega_dt = (missing): a spectral study needs omega_dt = "
            "{ from = .., to = .., points = .. } (log-spaced) or { values = [..] }");
  EXPECT_EQ(error_of(head + omega),
            "bad.toml:1:1: study.methods = (missing): a spectral study needs methods = "
            "[{ method = \"..\", .. }, ..]");
  EXPECT_EQ(error_of(head + methods + "omega_dt = { from = 0, to = 1, points = 3 }\n"),
            "bad.toml:4:21: study.omega_dt.from = 0: must be > 0 (the values are log-spaced)");
  EXPECT_EQ(error_of(head + methods + "omega_dt = { from = 1, to = 10, points = 1 }\n"),
            "bad.toml:4:42: study.omega_dt.points = 1: must be >= 2 (both ends are included)");
  EXPECT_EQ(error_of(head + methods + "omega_dt = { values = [1, -2] }\n"),
            "bad.toml:4:27: study.omega_dt.values[1] = -2: must be > 0");
  EXPECT_EQ(error_of(head + methods + "omega_dt = { from = 1, to = 10, partitions = 3 }\n"),
            "bad.toml:4:46: study.omega_dt.partitions = 3: unknown key (omega_dt keys: from, to, "
            "points, values)");
  EXPECT_EQ(error_of(head + omega + "methods = [{ method = \"hht\", alpha = -0.7 }]\n"),
            "bad.toml:4:38: study.methods[0].alpha = -0.7: must lie in [-0.5, 0]");
  EXPECT_EQ(error_of(head + omega +
                     "methods = [{ method = \"cdm\" }, { method = \"cdm\", "
                     "delta = 0.3 }]\n"),
            "bad.toml:4:58: study.methods[1].delta = 0.3: is not a parameter of method cdm (it "
            "applies to newmark|hht)");
  EXPECT_STARTS_WITH(error_of(head + omega + "methods = [{ method = \"cdm\", elements = 3 }]\n"),
                     "bad.toml:4:41: study.methods[0].elements = 3: unknown key (method keys: "
                     "method, delta, alpha, ");
  EXPECT_EQ(
      error_of(head + omega + "methods = [{ delta = 0.3 }]\n"),
      "bad.toml:4:12: study.methods[0].method = (missing): each method needs method = "
      "one of cdm|backward-euler|newmark|hht|generalized-alpha|bathe|rho-bathe|tr-bdf2|houbolt|"
      "wilson-theta|noh-bathe|kim-explicit|kr-alpha");
  EXPECT_EQ(error_of(head + omega + "methods = [{ method = \"rk4\" }]\n"),
            "bad.toml:4:23: study.methods[0].method = \"rk4\": must be one of "
            "cdm|backward-euler|newmark|hht|generalized-alpha|bathe|rho-bathe|tr-bdf2|houbolt|"
            "wilson-theta|noh-bathe|kim-explicit|kr-alpha");
  EXPECT_EQ(error_of(head + omega + "methods = [{ method = \"cdm\" }, { method = \"cdm\" }]\n"),
            "bad.toml:4:32: study.methods[1] = { method = \"cdm\" }: repeats study.methods[0] "
            "(cdm)");
  EXPECT_EQ(error_of(head + omega + "methods = []\n"),
            "bad.toml:4:11: study.methods = []: must hold at least one method");
  EXPECT_EQ(error_of(head + omega + methods + "alpha = { from = -0.7, to = 0, partitions = 2 }\n"),
            "bad.toml:5:9: study.alpha = { from = -0.7, to = 0, partitions = 2 }: holds alpha = "
            "-0.7, which must lie in [-0.5, 0]");
  EXPECT_EQ(error_of(head + omega + methods + "delta = { values = [0.5, -0.1] }\n"),
            "bad.toml:5:9: study.delta = { values = [0.5, -0.1] }: holds delta = -0.1, which "
            "must be >= 0 and finite (eq. 13)");
  EXPECT_EQ(error_of(head + omega + methods + "stability_omega_max = 0\n"),
            "bad.toml:5:23: study.stability_omega_max = 0: must be > 0");
  EXPECT_EQ(error_of(head + omega + methods + "omega_dt_reference = \"one\"\n"),
            "bad.toml:5:22: study.omega_dt_reference = \"one\": must be a number");
  EXPECT_EQ(error_of(head + omega + methods + "practical = { eps_p = 0.03 }\n"),
            "bad.toml:5:13: study.practical = { eps_p = 0.03 }: is for grid and list studies (a "
            "spectral study has no indicators)");
  EXPECT_STARTS_WITH(error_of(head + omega + methods + "axes = {}\n"),
                     "bad.toml:5:8: study.axes = {}: unknown key (spectral keys: kind, omega_dt, ");
  // Sections that a spectral study would ignore are errors.
  EXPECT_EQ(error_of("[scene]\nelements = 3\n" + head + omega + methods),
            "bad.toml:1:1: scene = { elements = 3 }: a spectral study runs no simulation; give "
            "each method in study.methods");
  EXPECT_EQ(error_of("[method]\nname = \"hht\"\n" + head + omega + methods),
            "bad.toml:1:1: method = { name = \"hht\" }: a spectral study runs no simulation; "
            "give each method in study.methods");
  EXPECT_EQ(error_of(head + omega + methods + "[output]\nhistories = \"h\"\n"),
            "bad.toml:6:13: output.histories = \"h\": is not used by a spectral study (only "
            "output.file is)");
}

}  // namespace
}  // namespace impactid

namespace impactid {
namespace {

// A list point starts from [scene], [method] and [output], never from the point before it: a
// method and its parameters do not leak into the next point (plans/identical-dissipation.toml
// relies on it).
TEST(PlanList, MethodParametersDoNotLeakBetweenPoints) {
  const Plan plan = plan_of(
      "[study]\nkind = \"list\"\npoints = [\n  { method = \"newmark\", delta = 0.2 },\n"
      "  { method = \"cdm\" },\n  { method = \"hht\", alpha = -0.3 },\n"
      "  { method = \"generalized-alpha\", rho_inf = 0.5 },\n]\n");
  const PointSet points(plan);
  ASSERT_EQ(points.size(), 4);
  EXPECT_EQ(points.parameter_names(), (std::vector<std::string>{"delta", "alpha", "rho_inf"}));
  const auto sim = [&](long k) { return std::get<Simulation>(build(points.settings(k))); };
  EXPECT_EQ(kind_of(sim(1).method), MethodKind::central_difference);
  const Simulation third = sim(2);
  const auto* hht = std::get_if<HhtParams>(&third.method);
  ASSERT_NE(hht, nullptr);
  EXPECT_FALSE(hht->delta.has_value());  // not newmark's 0.2: the default -alpha
  const std::vector<double> cdm = points.parameter_values(1);
  for (const double v : cdm) EXPECT_TRUE(std::isnan(v));
  const std::vector<double> hht_values = points.parameter_values(2);
  EXPECT_EQ(hht_values[0], 0.3);  // delta in effect: -alpha
  EXPECT_EQ(hht_values[1], -0.3);
  EXPECT_TRUE(std::isnan(hht_values[2]));
}

}  // namespace
}  // namespace impactid
