// The exact solution of several bodies, against RodImpactExact (one rod and its walls), the closed
// forms of collinear rod impact (Graff 1975 ch. 2, Goldsmith 1960 ch. 4) worked out here by hand,
// and the conservation of momentum and energy.
#include "core/reference/chain_exact.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/scene.hpp"
#include "core/reference/exact_solution.hpp"

namespace impactid {
namespace {

constexpr double kE = 90.0, kRho = 7.85e-9;  // the paper's rod [MPa], [t/mm³]
const double kC = std::sqrt(kE / kRho);      // [mm/s]

Segment segment(double length, double area = 1.0) {
  return Segment{
      .length = length, .elements = 100, .youngs_modulus = kE, .density = kRho, .area = area};
}

Body body(std::string name, double velocity, double gap, std::vector<Segment> segments) {
  return Body{
      .name = std::move(name), .velocity = velocity, .gap = gap, .segments = std::move(segments)};
}

Scene scene_of(std::vector<Body> bodies) {
  Scene scene;
  scene.bodies = std::move(bodies);
  scene.t_end = 1e-3;  // only for validate(); ChainExact takes its own t_end
  return scene;
}

int contact_index(const Scene& scene, const std::string& name) {
  const std::vector<SceneContact> contacts = scene_contacts(scene);
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (contacts[k].name == name) return static_cast<int>(k);
  }
  ADD_FAILURE() << "no contact " << name;
  return 0;
}

// Samples on a grid plus exactly on (and just beside) every jump of both solutions.
std::vector<double> sample_times(double t_end, std::span<const double> jumps,
                                 const std::vector<double>& more_jumps) {
  std::vector<double> t;
  for (int i = 0; i <= 2000; ++i) t.push_back(t_end * i / 2000.0);
  for (const auto& list : {std::vector<double>(jumps.begin(), jumps.end()), more_jumps}) {
    for (const double j : list) {
      for (const double dt : {-1e-9, 0.0, 1e-9}) {
        if (j + dt >= 0.0 && j + dt <= t_end) t.push_back(j + dt);
      }
    }
  }
  std::sort(t.begin(), t.end());
  return t;
}

void expect_values_near(const ContactNodeValues& got, const ContactNodeValues& want,
                        double pressure_scale, double velocity_scale, double displacement_scale,
                        double t) {
  EXPECT_NEAR(got.pressure, want.pressure, 1e-9 * pressure_scale) << "t = " << t;
  EXPECT_NEAR(got.velocity, want.velocity, 1e-9 * velocity_scale) << "t = " << t;
  EXPECT_NEAR(got.displacement, want.displacement, 1e-9 * displacement_scale) << "t = " << t;
}

// 1. The paper's rod on a wall: the same values as RodImpactExact at every sample, jumps included.
TEST(ChainExact, OneRodOnAWallIsRodImpactExact) {
  const RodScene rod;
  const Scene scene = to_scene(rod);
  const double t_end = 3.0 * derive(rod).end_time;
  const ChainExact chain(scene, t_end);
  const RodImpactExact reference(rod);
  ASSERT_EQ(chain.contact_count(), 1);
  const std::span<const double> jumps = chain.jumps(0);
  ASSERT_EQ(jumps.size(), 2u);
  EXPECT_NEAR(jumps[0], reference.impact_time(), 1e-12 * t_end);
  EXPECT_NEAR(jumps[1], reference.release_time(), 1e-12 * t_end);

  const double p = kRho * kC * rod.velocity, v = rod.velocity;
  const double tolerance = 1e-6 * derive(rod).time_step;
  for (const double t :
       sample_times(t_end, jumps, {reference.impact_time(), reference.release_time()})) {
    expect_values_near(chain.at(0, t, tolerance), reference.at(t, tolerance), p, v, v * t_end, t);
  }
  // While on the wall the node stands exactly at the wall, as in RodImpactExact.
  EXPECT_EQ(chain.at(0, 0.5 * (jumps[0] + jumps[1]), 0.0).displacement, rod.gap);
  // On the release jump: the mean of the limits, ρcv0/2 and −v0/2.
  const ContactNodeValues on_jump = chain.at(0, jumps[1], tolerance);
  EXPECT_NEAR(on_jump.pressure, 0.5 * p, 1e-12 * p);
  EXPECT_NEAR(on_jump.velocity, -0.5 * v, 1e-12 * v);
}

// A uniform rod cut into segments of unequal lengths is the uncut rod: equal impedances transmit
// exactly (R = 0, T = 1), and the arrivals at the wall, sums of different travel times, merge.
TEST(ChainExact, CutRodIsTheUncutRod) {
  RodScene rod;
  rod.far_gap = 0.03;
  Scene scene = to_scene(rod);
  const double pieces[] = {1.3, 2.9, 0.7, 5.1, 3.3, 6.7};  // sum 20 = rod.length
  scene.bodies[0].segments.clear();
  for (const double length : pieces) scene.bodies[0].segments.push_back(segment(length));
  const RodImpactExact reference(rod);
  const double t_end = 3.3 * reference.period();
  const ChainExact chain(scene, t_end);
  const int right = contact_index(scene, "wall_right");
  // Up to 3.3 periods: four main contacts (three released) and three far ones, during each of
  // which node n turns from −V to +V: 4 + 3 + 3 jumps.
  EXPECT_EQ(chain.jumps(right).size(), 10u);
  const double p = kRho * kC * rod.velocity, v = rod.velocity;
  const double tolerance = 1e-12;
  for (const double t : sample_times(t_end, chain.jumps(right), {})) {
    expect_values_near(chain.at(right, t, tolerance), reference.at(t, tolerance), p, v, v * t_end,
                       t);
  }
}

// 1. The rod between two walls, both directions of flight, several periods: wall_right is
// RodImpactExact's contact node; wall_left's pressure follows the same schedule at the far wall.
TEST(ChainExact, RodBetweenTwoWallsIsRodImpactExact) {
  for (const double v0 : {1000.0, -1000.0}) {
    RodScene rod;
    rod.far_gap = 0.02;
    rod.velocity = v0;
    const Scene scene = to_scene(rod);
    const RodImpactExact reference(rod);
    const double t_end = 4.5 * reference.period();
    const ChainExact chain(scene, t_end);
    const int left = contact_index(scene, "wall_left"), right = contact_index(scene, "wall_right");

    const double speed = std::abs(v0), p = kRho * kC * speed;
    const double d = 2.0 * rod.length / kC, f = (rod.gap + *rod.far_gap) / speed;
    const double tolerance = 1e-6 * derive(rod).time_step;
    // Far-wall contacts: [start, start + D) with start = the first far impact + n·T.
    const double first_far = v0 > 0 ? rod.gap / speed + d + f : *rod.far_gap / speed;
    const auto far_pressure = [&](double t) {
      const double since = t - first_far;
      if (since < 0) return 0.0;
      const double phase = since - reference.period() * std::floor(since / reference.period());
      return phase < d ? p : 0.0;
    };
    std::vector<double> far_jumps;
    for (double start = first_far; start < t_end; start += reference.period()) {
      far_jumps.push_back(start);
      far_jumps.push_back(start + d);
    }
    // About 4 main and 4 far contacts, each a closing and a release.
    EXPECT_GE(chain.jumps(left).size(), 8u) << v0;
    EXPECT_GE(chain.jumps(right).size(), 8u) << v0;

    for (const double t : sample_times(t_end, chain.jumps(right), far_jumps)) {
      expect_values_near(chain.at(right, t, tolerance), reference.at(t, tolerance), p, speed,
                         speed * t_end, t);
      const bool near_far_jump = std::any_of(far_jumps.begin(), far_jumps.end(),
                                             [&](double j) { return std::abs(t - j) <= 1e-6; });
      if (!near_far_jump) {
        EXPECT_NEAR(chain.at(left, t, 0.0).pressure, far_pressure(t), 1e-9 * p) << v0 << " " << t;
        // While on the far wall, node 0 rests exactly at −far_gap (as node n rests at gap in
        // RodImpactExact), without the round-off of the flights that brought it there.
        if (far_pressure(t) > 0) {
          EXPECT_EQ(chain.at(left, t, 0.0).displacement, -*rod.far_gap) << t;
          EXPECT_EQ(chain.at(left, t, 0.0).velocity, 0.0) << t;
        }
      }
    }
  }
}

// 2. Equal rods: ρcA·v0/2 for 2L/c from g/v0; the striker stops, the target leaves at v0.
TEST(ChainExact, EqualRodsExchangeVelocities) {
  const double length = 20.0, area = 2.0, v0 = 1000.0, gap = 0.01;
  const Scene scene = scene_of({body("striker", v0, 0.0, {segment(length, area)}),
                                body("target", 0.0, gap, {segment(length, area)})});
  const double t_end = 3e-3;
  const ChainExact chain(scene, t_end);
  ASSERT_EQ(chain.contact_count(), 1);
  const double impact = gap / v0, release = impact + 2.0 * length / kC;
  const std::span<const double> jumps = chain.jumps(0);
  ASSERT_EQ(jumps.size(), 2u);
  EXPECT_NEAR(jumps[0], impact, 1e-12 * t_end);
  EXPECT_NEAR(jumps[1], release, 1e-12 * t_end);

  const double pressure = kRho * kC * v0 / 2.0;  // λ/A with λ = ρcA·v0/2
  const ContactNodeValues during = chain.at(0, 0.5 * (impact + release), 0.0);
  EXPECT_NEAR(during.pressure, pressure, 1e-12 * pressure);
  EXPECT_NEAR(chain.force(0, 0.5 * (impact + release)), pressure * area, 1e-12 * pressure);
  EXPECT_NEAR(during.velocity, v0 / 2.0, 1e-12 * v0);
  const ContactNodeValues after = chain.at(0, 0.5 * (release + t_end), 0.0);
  EXPECT_EQ(after.pressure, 0.0);
  EXPECT_NEAR(after.velocity, 0.0, 1e-12 * v0);
  // The striker's end came to rest at v0·t_impact + (v0/2)·(2L/c).
  EXPECT_NEAR(after.displacement, gap + v0 * length / kC, 1e-12 * length);

  // Before the impact the striker holds all; after the release the target, flying rigidly at v0.
  const double mass = kRho * area * length;
  for (const auto& [t, holder] : {std::pair{0.5 * impact, 0}, {release + 1e-9, 1}, {t_end, 1}}) {
    for (int b = 0; b < 2; ++b) {
      const ChainBalance balance = chain.body_balance_at(b, t);
      const double share = b == holder ? 1.0 : 0.0;
      EXPECT_NEAR(balance.momentum, share * mass * v0, 1e-12 * mass * v0) << t << " " << b;
      EXPECT_NEAR(balance.energy, share * 0.5 * mass * v0 * v0, 1e-12 * mass * v0 * v0)
          << t << " " << b;
    }
  }
}

// 3. A striker half as long: the same force for 2·L1/c, then the striker is at rest.
TEST(ChainExact, ShortStrikerStopsAfterItsOwnTransit) {
  const double l1 = 10.0, l2 = 20.0, v0 = 1000.0, gap = 0.01;
  const Scene scene =
      scene_of({body("striker", v0, 0.0, {segment(l1)}), body("target", 0.0, gap, {segment(l2)})});
  const double t_end = 2e-3;
  const ChainExact chain(scene, t_end);
  const double impact = gap / v0, release = impact + 2.0 * l1 / kC;
  const std::span<const double> jumps = chain.jumps(0);
  ASSERT_GE(jumps.size(), 2u);
  EXPECT_NEAR(jumps[0], impact, 1e-12 * t_end);
  EXPECT_NEAR(jumps[1], release, 1e-12 * t_end);
  // The force falls to 0 at the release and the striker's end stands still; the target's end
  // leaves later (2·L2/c after impact), which the contact does not see as a jump of its node.
  const double pressure = kRho * kC * v0 / 2.0;
  EXPECT_NEAR(chain.at(0, 0.5 * (impact + release), 0.0).pressure, pressure, 1e-12 * pressure);
  for (const double t : {release + 1e-7, impact + 2.0 * l2 / kC + 1e-7, t_end}) {
    const ContactNodeValues v = chain.at(0, t, 0.0);
    EXPECT_EQ(v.pressure, 0.0) << t;
    EXPECT_NEAR(v.velocity, 0.0, 1e-12 * v0) << t;
  }
  EXPECT_EQ(jumps.size(), 2u);
  // The striker holds nothing from its release on; the target carries the striker's momentum
  // and energy (it leaves with internal waves: v0 in its first half, 0 in its second).
  const double mass = kRho * l1;
  for (const double t : {release + 1e-9, 0.5 * (release + t_end), t_end}) {
    const ChainBalance striker = chain.body_balance_at(0, t);
    EXPECT_NEAR(striker.momentum, 0.0, 1e-12 * mass * v0) << t;
    EXPECT_NEAR(striker.energy, 0.0, 1e-12 * mass * v0 * v0) << t;
    const ChainBalance target = chain.body_balance_at(1, t);
    EXPECT_NEAR(target.momentum, mass * v0, 1e-12 * mass * v0) << t;
    EXPECT_NEAR(target.energy, 0.5 * mass * v0 * v0, 1e-12 * mass * v0 * v0) << t;
  }
}

// 4. Two equal rods at ±v0 meet as one rod meets a wall: ρcA·v0 for 2L/c, the node at rest.
TEST(ChainExact, SymmetricImpactIsARodOnAWall) {
  const double length = 20.0, v0 = 1000.0, gap = 0.02;
  const Scene scene = scene_of(
      {body("left", v0, 0.0, {segment(length)}), body("right", -v0, gap, {segment(length)})});
  const double t_end = 2e-3;
  const ChainExact chain(scene, t_end);

  RodScene rod;  // the same rod on a wall at half the gap
  rod.gap = gap / 2.0;
  const RodImpactExact reference(rod);
  const double tolerance = 1e-12;
  for (const double t :
       sample_times(t_end, chain.jumps(0), {reference.impact_time(), reference.release_time()})) {
    expect_values_near(chain.at(0, t, tolerance), reference.at(t, tolerance), kRho * kC * v0, v0,
                       v0 * t_end, t);
  }
  EXPECT_EQ(chain.jumps(0).size(), 2u);
  const double mid = 0.5 * (reference.impact_time() + reference.release_time());
  EXPECT_NEAR(chain.at(0, mid, 0.0).pressure, kRho * kC * v0, 1e-12 * kRho * kC * v0);
  EXPECT_EQ(chain.at(0, mid, 0.0).velocity, 0.0);
}

// The release of two rods at ±v0 when one is cut into two segments: both reflected waves reach
// the contact at t_impact + 2L/c, the cut one's as a sum of other travel times that differs by
// round-off. Merged, the contact releases once, with no needle of v0 in the node's velocity.
TEST(ChainExact, CoincidentArrivalsAreMerged) {
  const double length = 20.0, v0 = 1000.0, gap = 0.02;
  for (const double cut : {0.1, 0.2, 0.3, 0.35, 0.45, 0.55, 0.7, 0.9, 1.0 / 3.0, 1.0 / 7.0}) {
    const Scene scene =
        scene_of({body("left", v0, 0.0, {segment(length)}),
                  body("right", -v0, gap, {segment(cut * length), segment((1.0 - cut) * length)})});
    const ChainExact chain(scene, 1e-3);
    const std::span<const double> jumps = chain.jumps(0);
    ASSERT_EQ(jumps.size(), 2u) << "cut " << cut << ": jumps at " << jumps[1] << ", "
                                << (jumps.size() > 2 ? jumps[2] : 0.0);
    EXPECT_NEAR(jumps[1] - jumps[0], 2.0 * length / kC, 1e-12 * 1e-3) << cut;
    EXPECT_NEAR(chain.at(0, 0.5 * (jumps[1] + 1e-3), 0.0).velocity, -v0, 1e-9 * v0) << cut;
  }
}

// 5. A stepped rod on a wall: A at the wall end, 4A behind it. The wall's wave −v0 enters the 4A
// segment at the step; its reflection (R = (Z_A − Z_4A)/(Z_A + Z_4A) = −3/5 for the velocity)
// returns to the wall after 2·L_A/c and raises the force: r = v0/2 + (3/5)·v0 = 1.1·v0, so
// λ = 2·Z·r = 2.2·ρcA·v0 from then on (until the next wave: 2·L_A/c later, since L_A < L_4A).
TEST(ChainExact, SteppedRodForceFollowsTheReflectionCoefficient) {
  const double wide = 20.0, narrow = 10.0, area = 1.0, v0 = 1000.0, gap = 0.01;
  Scene scene =
      scene_of({body("rod", v0, 0.0, {segment(wide, 4.0 * area), segment(narrow, area)})});
  scene.right_wall = Wall{.gap = gap};
  const double t_end = 1e-3;
  const ChainExact chain(scene, t_end);
  const double impact = gap / v0, first_change = impact + 2.0 * narrow / kC;
  const std::span<const double> jumps = chain.jumps(0);
  ASSERT_GE(jumps.size(), 3u);
  EXPECT_NEAR(jumps[0], impact, 1e-12 * t_end);
  EXPECT_NEAR(jumps[1], first_change, 1e-12 * t_end);
  EXPECT_NEAR(jumps[2], first_change + 2.0 * narrow / kC, 1e-12 * t_end);

  const double z = kRho * kC * area;
  EXPECT_NEAR(chain.force(0, 0.5 * (impact + first_change)), z * v0, 1e-12 * z * v0);
  EXPECT_NEAR(chain.at(0, 0.5 * (impact + first_change), 0.0).pressure, kRho * kC * v0,
              1e-12 * kRho * kC * v0);
  EXPECT_NEAR(chain.force(0, first_change + narrow / kC), 2.2 * z * v0, 1e-12 * z * v0);
  EXPECT_EQ(chain.at(0, first_change + narrow / kC, 0.0).velocity, 0.0);
}

// 6. Momentum and energy: conserved without walls (two and three bodies of mixed materials,
// areas and segments); with walls the energy is conserved and the momentum changes by the walls'
// impulses ∫(λ_left − λ_right) dt.
TEST(ChainExact, MomentumAndEnergyAreConserved) {
  Segment steel{
      .length = 7.0, .elements = 10, .youngs_modulus = 210e3, .density = 7.85e-9, .area = 3.0};
  Segment soft{
      .length = 13.0, .elements = 10, .youngs_modulus = 90.0, .density = 1.2e-9, .area = 1.5};
  std::vector<Scene> scenes;
  scenes.push_back(scene_of(
      {body("a", 800.0, 0.0, {steel, soft}), body("b", -300.0, 0.004, {soft, segment(5.0, 2.0)})}));
  scenes.push_back(
      scene_of({body("a", 1000.0, 0.0, {segment(11.0)}), body("b", 0.0, 0.01, {soft, steel}),
                body("c", -200.0, 0.003, {segment(9.0, 0.5), soft})}));
  Scene walls = scenes.back();
  walls.left_wall = Wall{.gap = 0.05};
  walls.right_wall = Wall{.gap = 0.02};
  scenes.push_back(walls);

  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const Scene& scene = scenes[s];
    double momentum = 0.0, energy = 0.0;
    for (const Body& b : scene.bodies) {
      for (const Segment& seg : b.segments) {
        const double mass = seg.density * seg.area * seg.length;
        momentum += mass * b.velocity;
        energy += 0.5 * mass * b.velocity * b.velocity;
      }
    }
    const double t_end = 1e-3;
    const ChainExact chain(scene, t_end);
    long contact_jumps = 0;
    for (int k = 0; k < chain.contact_count(); ++k) contact_jumps += chain.jumps(k).size();
    EXPECT_GE(contact_jumps, 4) << "scene " << s << ": its contacts must close and open";
    EXPECT_GT(chain.events(), 20) << s;

    const std::vector<SceneContact> contacts = scene_contacts(scene);
    for (int i = 0; i <= 40; ++i) {
      const double t = t_end * i / 40.0;
      // The walls' impulse up to t, exact over the piecewise-constant forces.
      double impulse = 0.0;
      for (int k = 0; k < chain.contact_count(); ++k) {
        if (contacts[k].kind == ContactKind::bodies) continue;
        const double sign = contacts[k].kind == ContactKind::left_wall ? 1.0 : -1.0;
        std::vector<double> edges{0.0};
        for (const double j : chain.jumps(k)) {
          if (j < t) edges.push_back(j);
        }
        edges.push_back(t);
        for (std::size_t e = 0; e + 1 < edges.size(); ++e) {
          if (edges[e + 1] > edges[e]) {
            impulse += sign * chain.force(k, edges[e]) * (edges[e + 1] - edges[e]);
          }
        }
      }
      const ChainBalance b = chain.balance_at(t);
      EXPECT_NEAR(b.momentum, momentum + impulse, 1e-11 * std::abs(momentum) + 1e-20)
          << "scene " << s << " t = " << t;
      EXPECT_NEAR(b.energy, energy, 1e-11 * energy) << "scene " << s << " t = " << t;
    }
  }
}

// λ >= 0 always, and a closed contact's node never moves apart from the other side: the
// Signorini conditions at every jump of a mixed three-body scene.
TEST(ChainExact, ForcesAreCompressive) {
  Segment stiff{
      .length = 5.0, .elements = 10, .youngs_modulus = 200e3, .density = 7.8e-9, .area = 2.0};
  Scene scene = scene_of({body("a", 500.0, 0.0, {segment(11.0), stiff}),
                          body("b", 0.0, 0.0, {stiff, segment(3.0, 0.7)}),
                          body("c", -100.0, 0.002, {segment(17.0, 1.3)})});
  scene.right_wall = Wall{.gap = 0.0};
  const ChainExact chain(scene, 1e-3);  // some 2.5e5 events (6e6 by 3e-3: fronts multiply)
  for (int k = 0; k < chain.contact_count(); ++k) {
    EXPECT_FALSE(chain.jumps(k).empty()) << k;
    for (const double j : chain.jumps(k)) EXPECT_GE(chain.force(k, j), 0.0) << k << " " << j;
  }
}

// Contacts closed from t = 0 (gap 0, approaching) list a jump at 0 and average it there.
TEST(ChainExact, ContactClosedAtTimeZero) {
  RodScene rod;
  rod.gap = 0.0;
  const ChainExact chain(to_scene(rod), 1e-3);
  ASSERT_FALSE(chain.jumps(0).empty());
  EXPECT_EQ(chain.jumps(0)[0], 0.0);
  const double p = kRho * kC * rod.velocity;
  EXPECT_NEAR(chain.at(0, 0.0, 1e-12).pressure, 0.5 * p, 1e-12 * p);
  EXPECT_NEAR(chain.at(0, 0.0, 1e-12).velocity, 0.5 * rod.velocity, 1e-12 * rod.velocity);
  EXPECT_NEAR(chain.at(0, 1e-6, 0.0).pressure, p, 1e-12 * p);
}

// Bodies touching at gap 0 without approaching stay apart (no chatter, no events).
TEST(ChainExact, TouchingAtRestStaysOpen) {
  const Scene scene =
      scene_of({body("a", 100.0, 0.0, {segment(10.0)}), body("b", 100.0, 0.0, {segment(10.0)})});
  const ChainExact chain(scene, 1e-3);
  EXPECT_TRUE(chain.jumps(0).empty());
  EXPECT_EQ(chain.events(), 0);
  EXPECT_EQ(chain.at(0, 5e-4, 0.0).pressure, 0.0);
}

// Incommensurate segments multiply the fronts: the event cap stops the solve with a message.
TEST(ChainExact, EventCapThrows) {
  const Scene scene =
      scene_of({body("a", 1000.0, 0.0,
                     {segment(1.0), segment(std::sqrt(2.0), 2.0), segment(std::sqrt(3.0), 0.5)}),
                body("b", 0.0, 0.0, {segment(std::sqrt(5.0), 3.0)})});
  try {
    const ChainExact chain(scene, 1e-3, ChainExactOptions{.max_events = 1000});
    FAIL() << "no exception after " << chain.events() << " events";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("more than 1000 events"), std::string::npos) << e.what();
  }
}

TEST(ChainExact, RejectsInvalidInput) {
  Scene scene = scene_of({body("a", 1.0, 0.0, {segment(1.0)})});
  scene.right_wall = Wall{.gap = 0.1};
  EXPECT_THROW(ChainExact(scene, -1.0), std::invalid_argument);
  EXPECT_THROW(ChainExact(scene, 1e-3, ChainExactOptions{.max_events = 0}), std::invalid_argument);
  const ChainExact chain(scene, 1e-3);
  EXPECT_THROW(chain.at(0, 2e-3, 0.0), std::out_of_range);
  scene.bodies[0].segments[0].area = -1.0;
  EXPECT_THROW(ChainExact(scene, 1e-3), std::invalid_argument);
}

}  // namespace
}  // namespace impactid
