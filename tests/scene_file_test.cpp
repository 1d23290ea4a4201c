// Scenes of bodies in plans and scene files: what a [[scene.body]] table parses to, its mistakes
// reported as "file:line:column: key = value: what", dotted scene keys as sweep axes, every
// contact's indicators stored beside the primary's, and the same numbers on 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "metrics/indicator_table.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/plan/scene_path.hpp"
#include "study/studies/evaluation.hpp"
#include "study/studies/sweep.hpp"
#include "study/studies/work_precision.hpp"

namespace impactid {
namespace {

const char* kHopkinson = R"(
name = "h"
[scene]
courant = 0.5
[[scene.body]]
name = "striker"
velocity = 1000.0
[[scene.body.segment]]
length = 5.0
elements = 25
[[scene.body.segment]]
length = 5.0
elements = 25
area = 2.0

[[scene.body]]
name = "bar"
gap = 0.01
length = 30.0
elements = 150

[scene.wall.right]
gap = 0.02

[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
"body.striker.velocity" = { values = [500.0, 1000.0] }
alpha = { values = [-0.3, -0.2] }
)";

std::string error_of(const std::string& text) {
  try {
    parse_plan(text, "bad.toml");
  } catch (const PlanError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the plan was accepted:\n" << text;
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SceneFile, ABodiesTableParsesToItsScene) {
  const Plan plan = parse_plan(kHopkinson, "plans/h.toml");
  ASSERT_TRUE(plan.base.bodies.has_value());
  const Scene& s = *plan.base.bodies;
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_EQ(s.bodies[0].name, "striker");
  EXPECT_EQ(s.bodies[0].velocity, 1000.0);
  ASSERT_EQ(s.bodies[0].segments.size(), 2u);
  EXPECT_EQ(s.bodies[0].segments[1].area, 2.0);
  EXPECT_EQ(s.bodies[0].segments[1].elements, 25);
  EXPECT_EQ(s.bodies[1].gap, 0.01);
  EXPECT_EQ(s.bodies[1].segments[0].length, 30.0);          // a one-segment body's own keys
  EXPECT_EQ(s.bodies[1].segments[0].youngs_modulus, 90.0);  // the default
  ASSERT_TRUE(s.right_wall.has_value());
  EXPECT_EQ(s.right_wall->gap, 0.02);
  EXPECT_FALSE(s.left_wall.has_value());
  const auto built = build(plan.base);
  ASSERT_TRUE(std::holds_alternative<Simulation>(built));
  EXPECT_TRUE(std::get<Simulation>(built).bodies() != nullptr);
}

TEST(SceneFile, MistakesNameTheirKeyAndPlace) {
  EXPECT_EQ(error_of(replaced(kHopkinson, "area = 2.0", "area = \"big\"")),
            "bad.toml:14:8: scene.body.1.segment.2.area = \"big\": must be a number");
  EXPECT_EQ(error_of(replaced(kHopkinson, "gap = 0.01", "gab = 0.01")).substr(0, 46),
            "bad.toml:18:7: scene.body.2.gab = 0.01: unknow");
  EXPECT_EQ(error_of(replaced(kHopkinson, "length = 30.0", "length = 30.0\n[[scene.body.segment]]"))
                .substr(0, 64),
            "bad.toml:19:10: scene.body.2.length = 30.0: a body gives either ");
  // Range errors are validate()'s, reported at [scene] with the dotted key.
  EXPECT_EQ(error_of(replaced(kHopkinson, "elements = 150", "elements = 0")),
            "bad.toml:3:1: scene.body.bar.segment.1.elements = 0: must be an integer in [1, 1e7]");
  EXPECT_EQ(error_of(replaced(kHopkinson, "name = \"bar\"", "name = \"striker\"")),
            "bad.toml:3:1: scene.body.striker.name = \"striker\": is the name of an earlier body: "
            "names must be unique");
  EXPECT_EQ(error_of(replaced(kHopkinson, "courant = 0.5", "courant = 0.5\nlength = 3.0")),
            "bad.toml:5:10: scene.length = 3.0: is a key of the one-body rod: a scene of bodies "
            "gives it on a body or a segment (body.<name>.velocity, "
            "body.<name>.segment.<k>.length, wall.right.gap, ...)");
}

TEST(SceneFile, AxisKeysMustNameANumberOfTheScene) {
  EXPECT_EQ(error_of(replaced(kHopkinson, "body.striker.velocity", "body.hammer.velocity")),
            "bad.toml:30:26: study.axes.body.hammer.velocity = { values = [500.0, 1000.0] }: names "
            "no body of the scene (by name, or its position from 1)");
  EXPECT_EQ(error_of(replaced(kHopkinson, "body.striker.velocity", "body.striker.segment.3.area")),
            "bad.toml:30:33: study.axes.body.striker.segment.3.area = { values = [500.0, 1000.0] "
            "}: names no segment of body striker (it has 2, counted from 1)");
  // Without bodies a scene key is refused at the axis.
  const std::string rod =
      "name = \"r\"\n[study]\nkind = \"grid\"\n[study.axes]\n"
      "\"body.a.velocity\" = { values = [1.0] }\n";
  EXPECT_EQ(error_of(rod).substr(0, 76),
            "bad.toml:5:21: study.axes.body.a.velocity = { values = [1.0] }: is a key of ");
}

TEST(ScenePath, PathsReadAndWriteTheScene) {
  Scene s = *parse_plan(kHopkinson, "h.toml").base.bodies;
  EXPECT_FALSE(assign_scene_path(s, "body.2.segment.1.area", 3.0).has_value());
  EXPECT_EQ(s.bodies[1].segments[0].area, 3.0);
  EXPECT_EQ(scene_path_value(s, "body.bar.segment.1.area"), 3.0);
  EXPECT_FALSE(assign_scene_path(s, "wall.right.gap", 0.5).has_value());
  EXPECT_EQ(s.right_wall->gap, 0.5);
  EXPECT_EQ(assign_scene_path(s, "wall.left.gap", 0.5)->constraint,
            "names a wall the scene does not have ([scene.wall.left])");
  EXPECT_EQ(assign_scene_path(s, "body.bar.segment.1.elements", 2.5)->constraint,
            "must be an integer below 2e9");
  EXPECT_EQ(assign_scene_path(s, "body.bar.colour", 1.0)->constraint,
            "is not a body key (velocity, gap, segment.<k>.<key>)");
  EXPECT_EQ(assign_scene_path(s, "body.striker.gap", 1.0)->constraint,
            "is the gap of the first body: the scene has no left wall");
}

// Doyen, Ern & Piperno's clamped bar (issue 36): the bar clamped on the right and released
// onto an obstacle on the left from u = ½(1 − x).
const char* kClampedBar = R"(
name = "c"
[scene]
courant = 1.0
t_end = 6.0
[[scene.body]]
name = "bar"
length = 1.0
elements = 20
youngs_modulus = 1.0
density = 1.0
displacement = [0.5, 0.0]
[scene.wall.left]
gap = 0.0
[scene.wall.right]
kind = "clamped"
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { values = [-0.3, -0.2] }
)";

TEST(SceneFile, AClampedWallAndADisplacementParse) {
  const Plan plan = parse_plan(kClampedBar, "plans/c.toml");
  ASSERT_TRUE(plan.base.bodies.has_value());
  const Scene& s = *plan.base.bodies;
  ASSERT_TRUE(s.right_wall && s.left_wall);
  EXPECT_EQ(s.right_wall->kind, WallKind::clamped);
  EXPECT_EQ(s.left_wall->kind, WallKind::contact);
  EXPECT_EQ(s.bodies[0].displacement, (LinearDisplacement{.left = 0.5, .right = 0.0}));
  // Without the keys: a contact wall and no displacement, the scene as it always was.
  const Scene plain = *parse_plan(kHopkinson, "plans/h.toml").base.bodies;
  EXPECT_EQ(plain.right_wall->kind, WallKind::contact);
  EXPECT_TRUE(plain.bodies[0].displacement.is_zero());
  EXPECT_TRUE(plain.bodies[1].displacement.is_zero());
}

TEST(SceneFile, ClampAndDisplacementMistakesNameTheirKeyAndPlace) {
  EXPECT_EQ(error_of(replaced(kClampedBar, "kind = \"clamped\"", "kind = \"fixed\"")),
            "bad.toml:16:8: scene.wall.right.kind = \"fixed\": \"fixed\" is not a kind of wall "
            "(\"contact\": a rigid obstacle, the default; \"clamped\": the end node held at u = "
            "0)");
  EXPECT_EQ(error_of(replaced(kClampedBar, "kind = \"clamped\"", "kind = 1")),
            "bad.toml:16:8: scene.wall.right.kind = 1: must be a string");
  EXPECT_EQ(error_of(replaced(kClampedBar, "kind = \"clamped\"", "side = 1")),
            "bad.toml:16:8: scene.wall.right.side = 1: unknown key (wall keys: kind, gap)");
  EXPECT_EQ(error_of(replaced(kClampedBar, "[0.5, 0.0]", "[0.5]")),
            "bad.toml:12:16: scene.body.1.displacement = [0.5]: must be an array of two "
            "numbers, [u at the body's first node, u at its last] in mm (linear in between)");
  EXPECT_EQ(error_of(replaced(kClampedBar, "[0.5, 0.0]", "[0.5, \"0\"]")),
            "bad.toml:12:22: scene.body.1.displacement[1] = \"0\": must be a number");
  // Range errors are validate()'s, reported at [scene] with the dotted key.
  EXPECT_EQ(error_of(replaced(kClampedBar, "kind = \"clamped\"", "kind = \"clamped\"\ngap = 0.1")),
            "bad.toml:3:1: scene.wall.right.gap = 0.1: a clamped end has no gap "
            "(wall.right.kind = \"clamped\"): give none");
  EXPECT_EQ(error_of(replaced(kClampedBar, "[0.5, 0.0]", "[0.5, 0.25]")),
            "bad.toml:3:1: scene.body.bar.displacement = [0.5, 0.25]: must be 0 at the clamped "
            "end (wall.right.kind = \"clamped\" holds the body's last node at u = 0)");
  EXPECT_EQ(error_of(replaced(kClampedBar, "[0.5, 0.0]", "[-0.5, 0.0]")),
            "bad.toml:3:1: scene.body.bar.displacement = [-0.5, 0]: closes contact wall_left past "
            "its gap at t = 0 (it closes 0.5 mm of a 0 mm gap): an initial state must keep every "
            "contact open or just closed");
  // A wall's kind is the scene file's: not an axis.
  EXPECT_EQ(error_of(replaced(kClampedBar, "alpha = { values", "\"wall.right.kind\" = { values")),
            "bad.toml:22:21: study.axes.wall.right.kind = { values = [-0.3, -0.2] }: is a wall's "
            "kind, a choice of the scene file ([scene.wall.right] kind = \"contact\" or "
            "\"clamped\"), not a number to vary or set");
}

TEST(ScenePath, TheDisplacementIsTwoNumbersInMillimetres) {
  Scene s = *parse_plan(kClampedBar, "c.toml").base.bodies;
  EXPECT_FALSE(assign_scene_path(s, "body.bar.displacement.left", 0.25).has_value());
  EXPECT_EQ(s.bodies[0].displacement.left, 0.25);
  EXPECT_FALSE(assign_scene_path(s, "body.1.displacement.right", -0.5).has_value());
  EXPECT_EQ(s.bodies[0].displacement.right, -0.5);
  EXPECT_EQ(scene_path_value(s, "body.bar.displacement.left"), 0.25);
  EXPECT_STREQ(scene_path_units("body.bar.displacement.left"), "mm");
  EXPECT_STREQ(scene_path_units("body.bar.displacement.right"), "mm");
  EXPECT_EQ(assign_scene_path(s, "body.bar.displacement", 1.0)->constraint,
            "is not a key of the body's initial displacement (displacement.left: u at its first "
            "node, displacement.right: at its last)");
  EXPECT_EQ(assign_scene_path(s, "body.bar.displacement.middle", 1.0)->constraint,
            "is not a key of the body's initial displacement (displacement.left: u at its first "
            "node, displacement.right: at its last)");
  EXPECT_EQ(assign_scene_path(s, "wall.right.kind", std::string("contact"))->field,
            "wall.right.kind");
}

// Gravity (Scene::gravity) is read from [scene], is a sweep path in mm/s², and is refused by name
// where it cannot be: on the one-body rod, on a model of matrices, without a wall toward it, and
// as anything but a number.
TEST(SceneFile, GravityIsReadSweptAndRefusedByName) {
  const std::string bar = replaced(kClampedBar, "courant = 1.0", "courant = 1.0\ngravity = -10.0");
  const Scene s = *parse_plan(bar, "c.toml").base.bodies;
  EXPECT_EQ(s.gravity, -10.0);
  Scene swept = s;
  EXPECT_FALSE(assign_scene_path(swept, "gravity", -5.0).has_value());
  EXPECT_EQ(swept.gravity, -5.0);
  EXPECT_EQ(scene_path_value(swept, "gravity"), -5.0);
  EXPECT_STREQ(scene_path_units("gravity"), "mm/s^2");
  EXPECT_EQ(assign_scene_path(swept, "gravity", std::string("down"))->constraint,
            "must be a number (mm/s^2, along x)");
  // The striker and bar have a right wall only: gravity toward the left has nothing to fall on.
  EXPECT_NE(error_of(replaced(kHopkinson, "courant = 0.5", "courant = 0.5\ngravity = -9810.0"))
                .find("scene.gravity = -9810: points toward the left end, and the scene has no "
                      "wall there (wall.left)"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(bar, "gravity = -10.0", "gravity = \"down\""))
                .find("scene.gravity = \"down\": must be a number"),
            std::string::npos);
  const std::string rod = "name = \"r\"\n[scene]\ngravity = -10.0\n[method]\nname = \"hht\"\n"
                          "[study]\nkind = \"list\"\npoints = [{ alpha = -0.1 }]\n";
  EXPECT_EQ(error_of(rod),
            "bad.toml:3:11: scene.gravity = -10.0: is a key of scenes of bodies ([[scene.body]]); "
            "this scene is the one-body rod (length, elements, velocity, gap, ...): write it as a "
            "body to give it");
}

StudyResults run_all(const Plan& plan, int threads) {
  const PointSet points(plan);
  StudyResults results = empty_results(plan, points);
  std::vector<long> indices(static_cast<std::size_t>(points.size()));
  for (long k = 0; k < points.size(); ++k) indices[static_cast<std::size_t>(k)] = k;
  SweepOptions options;
  options.threads = threads;
  run_sweep(points, indices, results, options);
  return results;
}

const ResultColumn* column(const StudyResults& r, const std::string& name) {
  for (const ResultColumn& c : r.indicators) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

TEST(SceneSweep, EveryContactIsStoredBesideThePrimaryOnAnyThreadCount) {
  const Plan plan = parse_plan(kHopkinson, "plans/h.toml");
  const StudyResults one = run_all(plan, 1);
  const StudyResults two = run_all(plan, 2);
  for (const char* name : {"eps_p", "eps_p.striker-bar", "eps_p.wall_right", "nop_v.wall_right",
                           "p_max.striker-bar", "contact_episodes.wall_right"}) {
    const ResultColumn* a = column(one, name);
    const ResultColumn* b = column(two, name);
    ASSERT_TRUE(a && b) << name;
    for (std::size_t i = 0; i < a->values.size(); ++i) {
      EXPECT_TRUE(a->values[i] == b->values[i] ||
                  (std::isnan(a->values[i]) && std::isnan(b->values[i])))
          << name << " point " << i;
    }
  }
  EXPECT_EQ(column(one, "eps_p.far_wall"), nullptr);
  // The primary contact is the first to close, striker-bar: its columns are the main ones.
  EXPECT_EQ(column(one, "eps_p")->values, column(one, "eps_p.striker-bar")->values);
  EXPECT_NE(column(one, "eps_p")->values, column(one, "eps_p.wall_right")->values);
  // The axis reached the scene: the faster striker presses harder.
  ASSERT_EQ(one.dimensions[0].name, "body.striker.velocity");
  EXPECT_EQ(one.dimensions[0].values, (std::vector<double>{500.0, 1000.0}));
  const auto& p = column(one, "p_max.striker-bar")->values;  // [velocity][alpha], alpha fastest
  ASSERT_EQ(one.status[0], 0);
  ASSERT_EQ(one.status[2], 0);
  EXPECT_GT(p[2], 1.5 * p[0]);
}

// A sweep runs consecutive points of one scene of bodies through the chain kernel in batches;
// each point must hold what `impactid simulate` (evaluate() alone) gives it, bit for bit.
void expect_batched_points_equal_points_alone(const Plan& plan) {
  const PointSet points(plan);
  ASSERT_TRUE(batchable_together(std::get<Simulation>(build(points.settings(0))),
                                 std::get<Simulation>(build(points.settings(1)))));
  const StudyResults batched = run_all(plan, 1);
  SimulationWorkspace ws;
  for (long k = 0; k < points.size(); ++k) {
    const Evaluation alone = evaluate(std::get<Simulation>(build(points.settings(k))), ws);
    const auto i = static_cast<std::size_t>(k);
    EXPECT_EQ(batched.status[i], static_cast<int>(alone.summary.status)) << k;
    for (const char* name : {"eps_p", "eps_v", "nop_p", "p_max"}) {
      const double want = find_indicator(name)->value(alone);
      const double got = column(batched, name)->values[i];
      EXPECT_TRUE(got == want || (std::isnan(got) && std::isnan(want)))
          << name << " point " << k << ": " << got << " vs " << want;
    }
  }
}

TEST(SceneSweep, BatchedPointsEqualThePointsRunAlone) {
  expect_batched_points_equal_points_alone(parse_plan(kHopkinson, "plans/h.toml"));
  // The paper's form written as a scene of bodies runs in the rod's kernel.
  const Plan paper = parse_plan(R"(
name = "paper as a body"
[scene]
t_end = 2e-4
[[scene.body]]
name = "rod"
velocity = 1000.0
[[scene.body.segment]]
length = 20.0
elements = 100
[scene.wall.right]
gap = 0.01
[method]
name = "hht"
[study]
kind = "grid"
[study.axes]
alpha = { from = -0.3, to = 0.0, partitions = 4 }
)",
                                "plans/p.toml");
  expect_batched_points_equal_points_alone(paper);
}

TEST(SceneSweep, AListPointSetsDottedKeysAndTheirColumnsKeepTheirUnits) {
  const std::string text = replaced(
      replaced(kHopkinson, "[method]\nname = \"hht\"\n", ""),
      "kind = \"grid\"\n[study.axes]\n\"body.striker.velocity\" = { values = [500.0, 1000.0] }\n"
      "alpha = { values = [-0.3, -0.2] }\n",
      "kind = \"list\"\npoints = [{ method = \"cdm\", \"body.bar.segment.1.area\" = 2.0 },\n"
      "          { method = \"hht\", \"body.striker.velocity\" = 500.0 }]\n");
  const Plan plan = parse_plan(text, "plans/l.toml");
  const StudyResults r = run_all(plan, 2);
  const ResultColumn* area = nullptr;
  const ResultColumn* velocity = nullptr;
  for (const ResultColumn& c : r.parameters) {
    if (c.name == "body.bar.segment.1.area") area = &c;
    if (c.name == "body.striker.velocity") velocity = &c;
  }
  ASSERT_TRUE(area && velocity);
  EXPECT_EQ(area->values, (std::vector<double>{2.0, 1.0}));  // the base scene's where not set
  EXPECT_EQ(velocity->values, (std::vector<double>{1000.0, 500.0}));
  EXPECT_EQ(area->units, "mm^2");
  EXPECT_EQ(velocity->units, "mm/s");
  EXPECT_EQ(error_of(replaced(text, "\"body.striker.velocity\" = 500.0",
                              "\"body.striker.colour\" = 500.0")),
            "bad.toml:28:53: study.points[1].body.striker.colour = 500.0: is not a body key "
            "(velocity, gap, segment.<k>.<key>)");
}

// A sweep over the clamped bar: measured against its exact solution, run point by point (the
// chain kernel refuses a clamp) with the numbers evaluate() gives each point alone, on any
// thread count.
TEST(SceneSweep, TheClampedBarIsMeasuredAgainstItsExactSolutionPointByPoint) {
  const Plan plan = parse_plan(kClampedBar, "plans/c.toml");
  const PointSet points(plan);
  EXPECT_FALSE(batchable_together(std::get<Simulation>(build(points.settings(0))),
                                  std::get<Simulation>(build(points.settings(1)))));
  const StudyResults one = run_all(plan, 1);
  const StudyResults two = run_all(plan, 2);
  SimulationWorkspace ws;
  for (long k = 0; k < points.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Evaluation alone = evaluate(std::get<Simulation>(build(points.settings(k))), ws);
    ASSERT_EQ(one.status[i], 0) << alone.summary.message;
    EXPECT_EQ(alone.reference,
              "exact solution of the clamped bar (core/reference/clamped_bar_exact.hpp)");
    EXPECT_EQ(column(one, "reference_refinements")->values[i], 0.0);
    for (const char* name : {"eps_p", "eps_v", "nop_p", "p_max", "energy_ratio"}) {
      const double want = find_indicator(name)->value(alone);
      EXPECT_EQ(column(one, name)->values[i], want) << name << " point " << k;
      EXPECT_EQ(column(two, name)->values[i], want) << name << " point " << k;
    }
    // 20 elements at Courant 1 with HHT: measured ε_p 0.30 (α = −0.3) and 0.41 (α = −0.2).
    EXPECT_LT(column(one, "eps_p")->values[i], 0.5) << k;
  }
}

// A reference that cannot be had (ChainExact's event cap, a refined run that is not ok) leaves
// the point failed with the reason, never indicators against nothing: planted in the
// workspace's cache, which evaluate() trusts for the same scene and options.
TEST(SceneEvaluation, WithoutAReferenceThePointFailsWithTheReason) {
  const auto built = build(parse_plan(kHopkinson, "plans/h.toml").base);
  const Simulation& sim = std::get<Simulation>(built);
  SimulationWorkspace workspace;
  workspace.reference =
      SceneReference{.scene = *sim.bodies(),
                     .options = ReferenceOptions{.tolerance = sim.indicators.reference_tolerance},
                     .converged = false,
                     .message = "ChainExact: more than 10000000 events"};
  const Evaluation e = evaluate(sim, workspace);
  EXPECT_EQ(e.summary.status, RunStatus::failed);
  EXPECT_EQ(e.summary.message, "no reference for the scene: ChainExact: more than 10000000 events");
  EXPECT_TRUE(std::isnan(e.indicators.eps_p));
  EXPECT_TRUE(std::isnan(e.contacts[0].eps_p));
  // The same workspace with its reference computed gives results.
  workspace.reference.reset();
  EXPECT_EQ(evaluate(sim, workspace).summary.status, RunStatus::ok);
}

// A work-precision study on a scene of bodies: `elements` is the scene's total, shared among the
// segments in the [scene] mesh's proportions, and the runs do the work they report.
TEST(SceneWorkPrecision, ElementsAreTheScenesTotalSharedAmongItsSegments) {
  std::string text = kHopkinson;
  text = text.substr(0, text.find("[method]")) +
         "[study]\nkind = \"work-precision\"\nmethods = [{ method = \"hht\" }]\n"
         "elements = [200, 400]\ncourant = [0.5]\nrepeats = 1\n";
  text = replaced(text, "courant = 0.5\n", "");  // the study sets it
  const Plan plan = parse_plan(text, "plans/w.toml");
  SimulationSettings settings;
  ASSERT_FALSE(assign_work_precision_point(plan, 0, 400, 0.5, settings).has_value());
  // [scene]: striker 25 + 25, bar 150 of 200 elements in all; twice as many here.
  EXPECT_EQ(settings.bodies->bodies[0].segments[0].elements, 50);
  EXPECT_EQ(settings.bodies->bodies[0].segments[1].elements, 50);
  EXPECT_EQ(settings.bodies->bodies[1].segments[0].elements, 300);
  StudyResults results = empty_work_precision_results(plan);
  run_work_precision(plan, results, {});
  bool found = false;
  for (const ResultColumn& c : results.indicators) {
    if (c.name == "dof_steps") {
      found = true;
      ASSERT_EQ(results.status[0], 0);
      // The assembled system's 202 nodes at 200 elements (51 + 151) and 402 at 400, with twice
      // the steps at the same Courant number: 3.98 times the work.
      EXPECT_GT(c.values[1], 3.9 * c.values[0]);
    }
  }
  EXPECT_TRUE(found);
}

// A damped scene's points are measured against the converged reference, and say so.
TEST(SceneSweep, ADampedSceneRecordsItsConvergedReference) {
  const std::string text =
      replaced(replaced(kHopkinson, "courant = 0.5", "courant = 0.5\nrayleigh_stiffness = 1e-8"),
               "alpha = { values = [-0.3, -0.2] }", "alpha = { values = [-0.3] }");
  const Plan plan = parse_plan(text, "plans/d.toml");
  const StudyResults r = run_all(plan, 2);
  const ResultColumn* refinements = column(r, "reference_refinements");
  const ResultColumn* change = column(r, "reference_change");
  ASSERT_TRUE(refinements && change);
  for (std::size_t i = 0; i < refinements->values.size(); ++i) {
    ASSERT_EQ(r.status[i], 0);
    EXPECT_GE(refinements->values[i], 2.0);
    EXPECT_LT(change->values[i], 1e-2);  // the default reference_tolerance
  }
  // The undamped plan's points use the exact solution.
  const StudyResults exact = run_all(parse_plan(kHopkinson, "plans/h.toml"), 2);
  EXPECT_EQ(column(exact, "reference_refinements")->values[0], 0.0);
  EXPECT_TRUE(std::isnan(column(exact, "reference_change")->values[0]));
}

TEST(SceneFile, ASceneFileGivesTheSettingsOfItsScene) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "impactid_scene_file";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "s.toml";
  std::ofstream(file) << "courant = 0.25\n[[body]]\nname = \"a\"\nvelocity = 10.0\n"
                         "[[body]]\nname = \"b\"\ngap = 0.5\n";
  const SimulationSettings s = load_scene_file(file);
  ASSERT_TRUE(s.bodies.has_value());
  EXPECT_EQ(s.bodies->bodies.size(), 2u);
  EXPECT_EQ(s.scene.courant, 0.25);
  std::ofstream(file) << "[[body]]\nname = \"a\"\nvelocity = 10.0\n";
  try {
    load_scene_file(file);
    ADD_FAILURE() << "a scene without a contact was accepted";
  } catch (const PlanError& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() +
                  ":1:1: scene.body = a: a scene needs at least one contact (a wall "
                  "or a second body)");
  }
}

}  // namespace
}  // namespace impactid
