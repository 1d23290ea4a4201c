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
