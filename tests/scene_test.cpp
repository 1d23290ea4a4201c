// Scenes of several bodies: validation messages, derived quantities (the one-body shorthand gives
// the rod's), the contact list, and the assembled system's structure.
#include "core/model/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/model/scene_assembly.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {
namespace {

Segment steel(double length, int elements, double area = 1.0) {
  return Segment{.length = length, .elements = elements, .area = area};
}

// A striker of length 10 at 1000 mm/s, 0.01 mm from a bar of length 30 at rest.
Scene hopkinson() {
  Scene s;
  s.bodies.push_back(Body{.name = "striker", .velocity = 1000.0, .segments = {steel(10, 100)}});
  s.bodies.push_back(Body{.name = "bar", .gap = 0.01, .segments = {steel(30, 300)}});
  return s;
}

TEST(Scene, OneBodyShorthandDerivesTheRodsGridBitForBit) {
  for (const RodScene& rod : {RodScene{}, RodScene{.elements = 37, .gap = 0.3, .courant = 0.9},
                              RodScene{.velocity = -5.0, .far_gap = 0.02}}) {
    const RodSceneDerived expected = derive(rod);
    const Scene scene = to_scene(rod);
    ASSERT_FALSE(validate(scene).has_value());
    const SceneDerived d = derive(scene);
    EXPECT_EQ(d.time_step, expected.time_step);
    EXPECT_EQ(d.end_time, expected.end_time);
    EXPECT_EQ(d.step_count, expected.step_count);
    EXPECT_EQ(d.initial_energy, expected.initial_energy);
    EXPECT_EQ(scene_contacts(scene)[static_cast<std::size_t>(d.primary_contact)].name,
              "wall_right");
  }
  // The default end time of the shorthand without stating it: the rod's rule is the scene's.
  Scene plain = to_scene(RodScene{});
  plain.t_end.reset();
  EXPECT_EQ(derive(plain).end_time, derive(RodScene{}).end_time);
}

TEST(Scene, ContactsAreListedLeftToRightWithTheirAreasAndClosingTimes) {
  Scene s = hopkinson();
  s.bodies[0].segments = {steel(5, 50, 2.0), steel(5, 50, 3.0)};
  s.left_wall = Wall{.gap = 0.5};
  s.right_wall = Wall{.gap = 0.2};
  const auto contacts = scene_contacts(s);
  ASSERT_EQ(contacts.size(), 3u);
  EXPECT_EQ(contacts[0].name, "wall_left");
  EXPECT_EQ(contacts[0].area, 2.0);  // the first body's first segment
  EXPECT_TRUE(std::isinf(contacts[0].rigid_closing_time));
  EXPECT_EQ(contacts[1].name, "striker-bar");
  EXPECT_EQ(contacts[1].area, 3.0);  // the left body's end segment
  EXPECT_DOUBLE_EQ(contacts[1].rigid_closing_time, 1e-5);
  EXPECT_EQ(contacts[2].name, "wall_right");
  EXPECT_TRUE(std::isinf(contacts[2].rigid_closing_time));  // the bar is at rest
}

TEST(Scene, DefaultEndTimeFollowsTheFirstContactAndItsLongestBody) {
  const Scene s = hopkinson();
  const SceneDerived d = derive(s);
  const double c = std::sqrt(90.0 / 7.85e-9);
  EXPECT_DOUBLE_EQ(d.first_contact_time, 1e-5);
  EXPECT_DOUBLE_EQ(d.end_time,
                   1e-5 + 1.5 * 2.0 * 30.0 / c);  // the bar's transit, not the striker's
  EXPECT_DOUBLE_EQ(d.time_step, 0.5 * 0.1 / c);
  EXPECT_EQ(d.nodes, 101 + 301);
}

TEST(Scene, TheStepComesFromTheSegmentWithTheSmallestHOverC) {
  Scene s = hopkinson();
  s.bodies[1].segments = {steel(30, 300),
                          Segment{.length = 1, .elements = 40, .youngs_modulus = 360}};
  const double c_stiff = std::sqrt(360.0 / 7.85e-9);
  EXPECT_DOUBLE_EQ(derive(s).time_step, 0.5 * (1.0 / 40) / c_stiff);
}

TEST(Scene, BadScenesNameTheKeyAndTheValue) {
  const auto error_of = [](const Scene& s) {
    const auto e = validate(s);
    return e ? e->field + " = " + e->value + ": " + e->constraint : std::string("none");
  };
  EXPECT_EQ(error_of(Scene{}), "body = none: a scene needs at least one body");
  Scene s = hopkinson();
  s.bodies[1].name = "striker";
  EXPECT_EQ(
      error_of(s),
      "body.striker.name = \"striker\": is the name of an earlier body: names must be unique");
  s = hopkinson();
  s.bodies[1].segments[0].elements = 0;
  EXPECT_EQ(error_of(s), "body.bar.segment.1.elements = 0: must be an integer in [1, 1e7]");
  s = hopkinson();
  s.bodies[1].gap = -0.1;
  EXPECT_EQ(error_of(s), "body.bar.gap = -0.1: must be >= 0 and finite (bodies may not overlap)");
  s = hopkinson();
  s.bodies[0].segments.push_back(Segment{.area = 0.0});
  EXPECT_EQ(error_of(s), "body.striker.segment.2.area = 0: must be positive and finite");
  s = hopkinson();
  s.bodies[0].name = "has space";
  EXPECT_EQ(error_of(s).substr(0, 27), "body.has space.name = \"has ");
  s = hopkinson();
  s.primary_contact = "wall_right";
  EXPECT_EQ(error_of(s),
            "primary_contact = \"wall_right\": is not a contact of the scene (striker-bar)");
  s = hopkinson();
  s.courant = 1e-9;
  EXPECT_EQ(error_of(s).substr(0, 42), "courant = 1e-09: gives more than 1e8 time ");
  s = hopkinson();
  s.right_wall = Wall{.gap = -1.0};
  EXPECT_EQ(error_of(s), "wall.right.gap = -1: must be >= 0 and finite");
  s = hopkinson();
  s.bodies.pop_back();
  EXPECT_EQ(error_of(s),
            "body = striker: a scene needs at least one contact (a wall or a second body)");
}

// Issue 38: the samples of a run with many contacts outgrow memory long before 1e8 steps, and a
// model (kind = "matrices") had no bound at all. Every scene kind checks both before it runs.
TEST(Scene, TheTimeGridIsBoundedInStepsAndInTheBytesOfItsSamples) {
  // 5e7 steps: 2.4 GB with one contact, 16.8 GB with 20.
  EXPECT_FALSE(validate_time_grid("dt", 1e-9, 1e-9, 0.05, "", 1));
  const auto e = validate_time_grid("dt", 1e-9, 1e-9, 0.05, "", 20);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->field, "dt");
  EXPECT_EQ(e->constraint,
            "gives 5e+07 time steps up to t_end = 0.05 s, whose 20 contacts' samples would take "
            "17.6 GB, more than the 8 GB a run may keep (a larger step or a shorter t_end)");
  // The rod's largest grid stays within the bytes: only the step count bounds it.
  EXPECT_FALSE(validate_time_grid("dt", 1e-9, 1e-9, 0.0999, "", 1));
  EXPECT_EQ(validate_time_grid("dt", 1e-9, 1e-9, 0.2, "", 1)->constraint.substr(0, 27),
            "gives more than 1e8 time st");
}

TEST(SceneAssembly, BodiesAreUncoupledBlocksAndContactsListTheirEndNodes) {
  Scene s = hopkinson();
  s.right_wall = Wall{.gap = 0.1};
  const AssembledScene a = assemble(s);
  const SecondOrderSystem& sys = a.system;
  ASSERT_EQ(sys.size(), 402);
  EXPECT_EQ(sys.stiffness.upper[100], 0.0);  // striker's last node – bar's first node
  EXPECT_EQ(sys.stiffness.lower[101], 0.0);
  EXPECT_EQ(sys.mass.upper[100], 0.0);
  EXPECT_FALSE(sys.has_contact());  // the named contact is unused: the list holds them
  ASSERT_EQ(sys.constraints.size(), 2u);
  EXPECT_EQ(sys.constraints[0].plus, 100);
  EXPECT_EQ(sys.constraints[0].minus, 101);
  EXPECT_EQ(sys.constraints[0].gap, 0.01);
  EXPECT_EQ(sys.constraints[1].plus, 401);
  EXPECT_EQ(sys.constraints[1].minus, -1);
  EXPECT_EQ(a.initial_velocity[100], 1000.0);
  EXPECT_EQ(a.initial_velocity[101], 0.0);
  EXPECT_EQ(a.probes[0].velocity_dof, 100);
  EXPECT_EQ(a.primary, 0);
  // A stepped body: its junction node carries both segments' stiffness and mass.
  Scene stepped = hopkinson();
  stepped.bodies[0].segments = {steel(5, 50, 1.0), steel(5, 50, 4.0)};
  const SecondOrderSystem st = assemble(stepped).system;
  const double k1 = 90.0 * 1.0 / 0.1, k4 = 90.0 * 4.0 / 0.1;
  EXPECT_DOUBLE_EQ(st.stiffness.diag[50], k1 + k4);
  EXPECT_DOUBLE_EQ(st.mass.diag[50], 0.5 * 7.85e-9 * 0.1 * (1.0 + 4.0));
}

// Doyen, Ern & Piperno's clamped bar as a scene: one bar of n elements (L = E = ρ = A = 1), an
// obstacle on the left at gap 0, clamped on the right, released from u = a·(1 − x).
Scene clamped_bar(int n, double a = 0.5) {
  Scene s;
  s.bodies.push_back(Body{
      .name = "bar",
      .segments = {Segment{.length = 1.0, .elements = n, .youngs_modulus = 1.0, .density = 1.0}},
      .displacement = {.left = a, .right = 0.0}});
  s.left_wall = Wall{.gap = 0.0};
  s.right_wall = Wall{.kind = WallKind::clamped};
  s.t_end = 6.0;
  return s;
}

TEST(Scene, AClampedWallIsNoContactAndItsBodyDoesNotStartFree) {
  const Scene s = clamped_bar(10);
  ASSERT_FALSE(validate(s).has_value()) << validate(s)->constraint;
  const auto contacts = scene_contacts(s);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].name, "wall_left");
  EXPECT_FALSE(bodies_start_free(s));
  EXPECT_FALSE(in_paper_form(s));
  EXPECT_FALSE(as_rod(s).has_value());
  // The paper's one-body form with an initial displacement is not the paper's rod either:
  // RodScene cannot say it.
  Scene displaced = to_scene(RodScene{});
  ASSERT_TRUE(as_rod(displaced).has_value());
  displaced.bodies[0].displacement = {.left = 0.0, .right = -0.001};
  ASSERT_FALSE(validate(displaced).has_value());
  EXPECT_FALSE(bodies_start_free(displaced));
  EXPECT_FALSE(as_rod(displaced).has_value());
  // A clamp alone, with a contact wall on the other side: the clamp is not the paper's wall.
  Scene clamped_rod = to_scene(RodScene{});
  clamped_rod.right_wall = Wall{.kind = WallKind::clamped};
  clamped_rod.left_wall = Wall{.gap = 0.01};
  clamped_rod.primary_contact.reset();  // the shorthand's wall_right is no contact any more
  ASSERT_FALSE(validate(clamped_rod).has_value()) << validate(clamped_rod)->constraint;
  EXPECT_FALSE(as_rod(clamped_rod).has_value());
  EXPECT_TRUE(bodies_start_free(hopkinson()));
  EXPECT_STREQ(to_string(WallKind::clamped), "clamped");
  EXPECT_EQ(wall_kind_from_string("contact"), WallKind::contact);
  EXPECT_FALSE(wall_kind_from_string("fixed").has_value());
}

TEST(Scene, TheInitialStrainEntersTheEnergyTheVelocityScaleAndTheClosingTimes) {
  const SceneDerived d = derive(clamped_bar(10));
  EXPECT_DOUBLE_EQ(d.initial_energy, 0.125);  // ½·E·A·L·ε², ε = −½: the benchmark's 1/8
  EXPECT_DOUBLE_EQ(d.velocity_scale, 0.5);    // c·|ε|: the contact end's speed a·c/L
  EXPECT_TRUE(std::isinf(d.first_contact_time));  // at rest: no rigid closing
  EXPECT_EQ(d.nodes, 11);                         // the clamped node counted
  // A displacement toward the gap closes part of it: the rigid closing time is the rest over
  // the approach velocity.
  Scene s = hopkinson();
  s.bodies[1].displacement = {.left = -0.004, .right = -0.004};  // the bar shifted 4 µm left
  EXPECT_DOUBLE_EQ(scene_contacts(s)[0].rigid_closing_time, 0.006 / 1000.0);
  s.bodies[0].displacement = {.left = 0.002, .right = 0.002};
  EXPECT_DOUBLE_EQ(scene_contacts(s)[0].rigid_closing_time, 0.004 / 1000.0);
  EXPECT_DOUBLE_EQ(derive(s).velocity_scale, 1000.0);  // rigid shifts carry no strain
}

TEST(Scene, ClampsAndInitialDisplacementsAreValidatedByKey) {
  const auto error_of = [](const Scene& s) {
    const auto e = validate(s);
    return e ? e->field + " = " + e->value + ": " + e->constraint : std::string("none");
  };
  Scene s = clamped_bar(10);
  s.right_wall->gap = 0.1;
  EXPECT_EQ(error_of(s),
            "wall.right.gap = 0.1: a clamped end has no gap (wall.right.kind = \"clamped\"): give "
            "none");
  s = clamped_bar(10);
  s.bodies[0].displacement.right = 0.1;
  EXPECT_EQ(error_of(s),
            "body.bar.displacement = [0.5, 0.1]: must be 0 at the clamped end (wall.right.kind = "
            "\"clamped\" holds the body's last node at u = 0)");
  s = clamped_bar(10);
  s.bodies[0].displacement.left = -0.5;  // past the obstacle at t = 0
  EXPECT_EQ(error_of(s),
            "body.bar.displacement = [-0.5, 0]: closes contact wall_left past its gap at t = 0 "
            "(it closes 0.5 mm of a 0 mm gap): an initial state must keep every contact open or "
            "just closed");
  s = clamped_bar(10);
  s.bodies[0].displacement.left = std::nan("");
  EXPECT_EQ(error_of(s),
            "body.bar.displacement = [nan, 0]: must be finite ([u at the first node, u at the "
            "last node], mm)");
  s = clamped_bar(10);
  s.left_wall = Wall{.kind = WallKind::clamped};
  s.bodies[0].displacement = {};
  EXPECT_EQ(error_of(s),
            "body = bar: a scene needs at least one contact (a wall or a second body; a clamped "
            "wall is none)");
  s = clamped_bar(10);
  s.left_wall = Wall{.kind = WallKind::clamped};
  EXPECT_EQ(error_of(s),
            "body.bar.displacement = [0.5, 0]: must be 0 at the clamped end (wall.left.kind = "
            "\"clamped\" holds the body's first node at u = 0)");
  // Two bodies overlapping at t = 0: named at the body whose displacement closes the gap.
  s = hopkinson();
  s.bodies[0].displacement = {.left = 0.0, .right = 0.02};
  EXPECT_EQ(error_of(s),
            "body.striker.displacement = [0, 0.02]: closes contact striker-bar past its gap at t = "
            "0 (it closes 0.02 mm of a 0.01 mm gap): an initial state must keep every contact open "
            "or just closed");
  s.bodies[0].displacement = {.left = 0.0, .right = 0.01};  // just closed: allowed
  EXPECT_EQ(error_of(s), "none");
}

TEST(SceneAssembly, AClampedNodeIsNoDofAndTheDisplacementIsLinear) {
  const int n = 10;
  const double h = 1.0 / n;
  const Scene s = clamped_bar(n);
  const AssembledScene a = assemble(s);
  const SecondOrderSystem& sys = a.system;
  // n + 1 nodes less the clamped one; K and M are the free bar's without its last row and column.
  Scene free_bar = s;
  free_bar.right_wall.reset();
  free_bar.bodies[0].displacement = {};
  const SecondOrderSystem full = assemble(free_bar).system;
  ASSERT_EQ(full.size(), n + 1);
  ASSERT_EQ(sys.size(), n);
  EXPECT_EQ(sys.stiffness.diag, full.stiffness.diag.head(n));
  EXPECT_EQ(sys.stiffness.lower.tail(n - 1), full.stiffness.lower.segment(1, n - 1));
  EXPECT_EQ(sys.stiffness.upper.head(n - 1), full.stiffness.upper.head(n - 1));
  EXPECT_EQ(sys.stiffness.upper[n - 1], 0.0);            // the coupling to the clamp is gone
  EXPECT_DOUBLE_EQ(sys.stiffness.diag[n - 1], 2.0 / h);  // both elements at the last free node
  EXPECT_DOUBLE_EQ(sys.stiffness.diag[0], 1.0 / h);      // the free end's one element
  EXPECT_EQ(sys.mass.diag, full.mass.diag.head(n));
  EXPECT_TRUE(sys.damping.is_zero());
  // The obstacle on the first DOF, as a listed constraint (not the paper's named contact).
  EXPECT_FALSE(sys.has_contact());
  ASSERT_EQ(sys.constraints.size(), 1u);
  EXPECT_EQ(sys.constraints[0].plus, -1);
  EXPECT_EQ(sys.constraints[0].minus, 0);
  EXPECT_EQ(sys.constraints[0].gap, 0.0);
  ASSERT_EQ(a.probes.size(), 1u);
  EXPECT_EQ(a.probes[0].velocity_dof, 0);
  // The initial state: u = ½(1 − x) at the nodes, at rest; its energy ½uᵀKu is the benchmark's
  // 1/8 exactly (a linear field is its own interpolant).
  ASSERT_EQ(a.initial_displacement.size(), n);
  for (int j = 0; j < n; ++j) EXPECT_DOUBLE_EQ(a.initial_displacement[j], 0.5 * (1.0 - j * h));
  EXPECT_EQ(a.initial_displacement[0], 0.5);
  EXPECT_TRUE(a.initial_velocity.isZero(0.0));
  EXPECT_NEAR(sys.energy(a.initial_displacement, a.initial_velocity), 0.125, 1e-15);
  EXPECT_FALSE(a.starts_free);
  EXPECT_FALSE(a.rigid_flight);
  // A consistent mass loses the clamp's coupling too.
  Scene consistent = s;
  consistent.mass = MassMatrix::consistent;
  const SecondOrderSystem c = assemble(consistent).system;
  EXPECT_EQ(c.mass.upper[n - 1], 0.0);
  EXPECT_DOUBLE_EQ(c.mass.diag[n - 1], 2.0 * h / 3.0);
}

TEST(SceneAssembly, AClampOnTheLeftShiftsEveryDofByOne) {
  Scene s = hopkinson();
  s.left_wall = Wall{.kind = WallKind::clamped};
  s.bodies[0].velocity = 0.0;
  s.bodies[1].velocity = -1000.0;
  s.bodies[0].displacement = {.left = 0.0, .right = 0.001};  // stretched striker
  s.right_wall = Wall{.gap = 0.1};
  ASSERT_FALSE(validate(s).has_value()) << validate(s)->constraint;
  const AssembledScene a = assemble(s);
  ASSERT_EQ(a.system.size(), 401);  // 101 + 301 nodes less the clamped first
  ASSERT_EQ(a.system.constraints.size(), 2u);
  EXPECT_EQ(a.system.constraints[0].plus, 99);  // striker's last node, 100, is DOF 99
  EXPECT_EQ(a.system.constraints[0].minus, 100);
  EXPECT_EQ(a.system.constraints[1].plus, 400);
  EXPECT_EQ(a.probes[0].velocity_dof, 99);
  EXPECT_EQ(a.system.stiffness.lower[0], 0.0);  // the coupling to the clamp is gone
  EXPECT_DOUBLE_EQ(a.system.stiffness.diag[0], 2.0 * 90.0 / 0.1);
  EXPECT_DOUBLE_EQ(a.initial_displacement[0], 0.001 * 0.01);  // node 1 at x = 0.1 of 10 mm
  EXPECT_EQ(a.initial_displacement[99], 0.001);               // the last node: exactly `right`
  EXPECT_EQ(a.initial_displacement[100], 0.0);                // the bar: undisplaced
  EXPECT_EQ(a.initial_velocity[0], 0.0);
  EXPECT_EQ(a.initial_velocity[100], -1000.0);
}

TEST(SceneAssembly, ThePapersSceneUsesTheNamedContactWithTheRodsMatrices) {
  const RodScene rod;
  const AssembledScene a = assemble(to_scene(rod));
  const SecondOrderSystem expected = assemble_rod(rod);
  EXPECT_TRUE(a.system.constraints.empty());
  EXPECT_EQ(a.system.contact_dof, expected.contact_dof);
  EXPECT_EQ(a.system.gap, expected.gap);
  EXPECT_EQ(a.system.mass.diag, expected.mass.diag);
  EXPECT_EQ(a.system.stiffness.diag, expected.stiffness.diag);
  EXPECT_EQ(a.system.stiffness.upper, expected.stiffness.upper);
  EXPECT_EQ(a.dt, derive(rod).time_step);
}

}  // namespace
}  // namespace impactid
