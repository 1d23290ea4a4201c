// The bouncing bar (Doyen, Ern & Piperno 2011), against its own invariants and closed forms,
// computed here from the problem's statement rather than from the class: the wave equation with
// gravity by finite differences of the displacement, the free top and the Signorini conditions
// at the ground, the rigid fall from rest, the period 16L/c, the conserved energy ρgL·(d + L/2)
// and each episode's impulse against the momentum the bar gains over it. Each test runs on the
// benchmark (L = 10, E = 900, ρ = 1, g = 10) and on a scaled bar.
#include "core/reference/bouncing_bar_exact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace impactid {
namespace {

// What the tests know of a bar, worked out from its parameters only.
struct Bar {
  BouncingBarParams params;
  double c, transit;  // c, D = L/c
  double gap;         // d = g·(3D)²/2: a fall of 3L/c from rest
  double speed;       // gD
  double length;      // gD²
  double stress;      // ρgL
  double energy;      // ρgL·(d + L/2)
};
Bar bar_of(const BouncingBarParams& p) {
  const double c = std::sqrt(p.youngs_modulus / p.density);
  const double transit = p.length / c;
  const double gap = 0.5 * p.gravity * (3.0 * transit) * (3.0 * transit);
  const double stress = p.density * p.gravity * p.length;
  return {p,
          c,
          transit,
          gap,
          p.gravity * transit,
          p.gravity * transit * transit,
          stress,
          stress * (gap + 0.5 * p.length)};
}
std::vector<Bar> bars() {
  return {bar_of(BouncingBarParams{}),
          bar_of(BouncingBarParams{
              .length = 2.0, .youngs_modulus = 50.0, .density = 0.5, .gravity = 3.0})};
}

// x = i·L/n, exactly L at i = n.
double node(int i, int n, double length) {
  return i == n ? length : length * i / n;
}

// The characteristics through the kinks, by the derivation: the lower end's emitted invariant
// jumps at τ = 3, 5, 7, 9, 11 (mod 16), seen along τ − ξ and, reflected at the top, along
// τ + ξ − 2. Distance of (x, t) to the nearest of them, in units of L/c.
double kink_distance(const Bar& bar, double x, double t) {
  const double tau = t / bar.transit, xi = x / bar.params.length;
  double nearest = std::numeric_limits<double>::infinity();
  for (const double s : {tau - xi, tau + xi - 2.0}) {
    const double r = s - 16.0 * std::floor(s / 16.0);
    for (const double jump : {3.0, 5.0, 7.0, 9.0, 11.0}) {
      nearest = std::min(nearest, std::abs(r - jump));
    }
  }
  return nearest;
}

// ∫ u(x, t) dx by the midpoint rule. Its error in a cell crossed by a kink at δ from the cell's
// edge is O(δ²), so the momentum it gives at a time when the kinks sit on the ends is exact to
// O(h) (the trapezoid rule's error there moves linearly with the kink: O(1/n) in the momentum).
double displacement_integral(const BouncingBarExact& exact, const Bar& bar, double t) {
  const int n = 4000;
  const double h = bar.params.length / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += exact.displacement((i + 0.5) * h, t);
  return sum * h;
}

// Released at rest and unstressed, the bar falls rigidly, u = −g·t²/2, until its lower end
// reaches the ground at √(2d/g) = 3L/c.
TEST(BouncingBarExact, RigidFallFromRest) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double g = bar.params.gravity, length = bar.params.length;
    EXPECT_DOUBLE_EQ(exact.initial_gap(), bar.gap);
    EXPECT_DOUBLE_EQ(exact.fall_time(), std::sqrt(2.0 * bar.gap / g));
    for (int j = 0; j < 60; ++j) {
      const double t = 3.0 * bar.transit * j / 60.0;
      for (int i = 0; i <= 20; ++i) {
        const double x = node(i, 20, length);
        const BarPointValues value = exact.point(x, t, 0.0);
        EXPECT_NEAR(value.displacement, -0.5 * g * t * t, 1e-13 * bar.gap) << x << ", " << t;
        EXPECT_NEAR(value.velocity, -g * t, 1e-13 * bar.speed) << x << ", " << t;
        EXPECT_EQ(value.stress, 0.0) << x << ", " << t;
      }
      EXPECT_FALSE(exact.in_contact(t)) << t;
    }
    EXPECT_TRUE(exact.in_contact(3.0 * bar.transit * (1.0 + 1e-12)));
    EXPECT_DOUBLE_EQ(exact.episodes(10.0 * bar.transit).front().start, exact.fall_time());
  }
}

// u_tt = c²·u_xx − g: the diamond of characteristics u(x, t+h) + u(x, t−h) − u(x+ch, t) −
// u(x−ch, t) equals −g·h² for every diamond inside the bar, kinks or not; and away from the
// kinks, where u is quadratic in x and t, the second differences satisfy the equation.
TEST(BouncingBarExact, WaveEquationWithGravity) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double g = bar.params.gravity, length = bar.params.length, c = bar.c;
    const double round_off = 1e-12 * 128.0 * bar.length;  // u's terms reach 128·gD²
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
      const double x = length * (0.02 + 0.96 * unit(random));
      const double t = 40.0 * bar.transit * unit(random);
      const double reach = 0.99 * std::min(x, length - x) * unit(random);
      const double h = reach / c;
      const double diamond = exact.displacement(x, t + h) + exact.displacement(x, t - h) -
                             exact.displacement(x + reach, t) - exact.displacement(x - reach, t);
      EXPECT_NEAR(diamond, -g * h * h, round_off) << "x = " << x << ", t = " << t << ", h = " << h;
    }
    int smooth = 0;
    for (int i = 0; i < 4000; ++i) {
      const double x = length * (0.02 + 0.96 * unit(random));
      const double t = 40.0 * bar.transit * unit(random);
      const double ht = 1e-3 * bar.transit, hx = 0.7e-3 * length;
      if (kink_distance(bar, x, t) < 3e-3) continue;
      ++smooth;
      const double u = exact.displacement(x, t);
      const double utt =
          (exact.displacement(x, t + ht) - 2 * u + exact.displacement(x, t - ht)) / (ht * ht);
      const double uxx =
          (exact.displacement(x + hx, t) - 2 * u + exact.displacement(x - hx, t)) / (hx * hx);
      EXPECT_NEAR(utt - c * c * uxx, -g, 1e-5 * g) << "x = " << x << ", t = " << t;
    }
    EXPECT_GT(smooth, 3000);
  }
}

// The top is free, the ground is never penetrated, the pressure pushes, and the two are
// complementary; the lower end's pressure and velocity are those of the displacement field.
TEST(BouncingBarExact, FreeTopAndSignoriniGround) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double length = bar.params.length, E = bar.params.youngs_modulus;
    const double tol = 1e-12 * bar.gap;
    const double h = 1e-3 * length, ht = 1e-3 * bar.transit;
    int held = 0, free = 0, top = 0;
    for (int i = 0; i <= 8000; ++i) {
      const double t = 32.0 * bar.transit * i / 8000.0;
      if (kink_distance(bar, length, t) > 3e-3) {
        // σ(L, t) = E·u_x(L, t) by the one-sided three-point difference (exact for quadratics).
        const double strain =
            (3 * exact.displacement(length, t) - 4 * exact.displacement(length - h, t) +
             exact.displacement(length - 2 * h, t)) /
            (2 * h);
        EXPECT_NEAR(E * strain, 0.0, 1e-8 * bar.stress) << t;
        ++top;
      }
      const ContactNodeValues end = exact.at(t, 0.0);
      const double gap = bar.gap + end.displacement;
      EXPECT_GE(gap, -tol) << t;
      EXPECT_GE(end.pressure, 0.0) << t;
      if (gap > tol) {
        EXPECT_EQ(end.pressure, 0.0) << t;
      }
      if (end.pressure > 0.0) {
        EXPECT_LE(std::abs(gap), tol) << t;
      }
      const double tau = std::fmod(t / bar.transit, 16.0);
      bool on_boundary = false;
      for (const double b : {3.0, 5.0, 11.0, 13.0}) on_boundary |= std::abs(tau - b) < 1e-9;
      if (!on_boundary) {
        EXPECT_EQ(exact.in_contact(t), std::abs(gap) <= tol) << t;
      }
      if (kink_distance(bar, 0.0, t) < 3e-3) continue;  // finite differences across a jump
      const double strain = (-3 * exact.displacement(0.0, t) + 4 * exact.displacement(h, t) -
                             exact.displacement(2 * h, t)) /
                            (2 * h);
      const double rate =
          (exact.displacement(0.0, t + ht) - exact.displacement(0.0, t - ht)) / (2 * ht);
      EXPECT_NEAR(end.pressure, -E * strain, 1e-8 * bar.stress) << t;
      EXPECT_NEAR(end.velocity, rate, 1e-8 * bar.speed) << t;
      (end.pressure > 0.0 ? held : free) += 1;
    }
    EXPECT_GT(held, 1500);
    EXPECT_GT(free, 5000);
    EXPECT_GT(top, 7000);
  }
}

// The lower end phase by phase (τ = t/D mod 16; u in gD², v in gD, p in ρgL), as the header's
// table, and the mean of the one-sided limits on a jump.
TEST(BouncingBarExact, ContactEndByPhase) {
  struct Phase {
    double from, to;
    double u2, u1, u0;  // u = u2·τ² + u1·τ + u0
    double v1, v0;      // v = v1·τ + v0
    double p1, p0;      // p = p1·τ + p0
  };
  const std::vector<Phase> phases{
      {0, 3, -0.5, 0, 0, -1, 0, 0, 0},        {3, 5, 0, 0, -4.5, 0, 0, 1, 0},
      {5, 7, 0.5, -4, 3, 1, -4, 0, 0},        {7, 9, 0.5, -8, 31, 1, -8, 0, 0},
      {9, 11, 0.5, -12, 67, 1, -12, 0, 0},    {11, 13, 0, 0, -4.5, 0, 0, -1, 16},
      {13, 16, -0.5, 16, -128, -1, 16, 0, 0},
  };
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    for (int period = 0; period < 3; ++period) {
      for (const Phase& phase : phases) {
        for (int i = 1; i < 50; ++i) {
          const double tau = phase.from + (phase.to - phase.from) * i / 50.0;
          const double t = (tau + 16.0 * period) * bar.transit;
          const ContactNodeValues end = exact.at(t, 0.0);
          const double scale = 1e-11 * (period + 1);
          EXPECT_NEAR(end.displacement / bar.length, (phase.u2 * tau + phase.u1) * tau + phase.u0,
                      128 * scale)
              << t;
          EXPECT_NEAR(end.velocity / bar.speed, phase.v1 * tau + phase.v0, 16 * scale) << t;
          EXPECT_NEAR(end.pressure / bar.stress, phase.p1 * tau + phase.p0, 16 * scale) << t;
        }
      }
    }
    const double tolerance = 1e-9 * bar.transit;
    const auto at_tau = [&](double tau) { return exact.at(tau * bar.transit, tolerance); };
    EXPECT_NEAR(at_tau(3).pressure, 1.5 * bar.stress, 1e-12 * bar.stress);   // 0 → 3
    EXPECT_NEAR(at_tau(3).velocity, -1.5 * bar.speed, 1e-12 * bar.speed);    // −3 → 0
    EXPECT_NEAR(at_tau(5).pressure, 2.5 * bar.stress, 1e-12 * bar.stress);   // 5 → 0
    EXPECT_NEAR(at_tau(5).velocity, 0.5 * bar.speed, 1e-12 * bar.speed);     // 0 → 1
    EXPECT_NEAR(at_tau(7).velocity, 1.0 * bar.speed, 1e-12 * bar.speed);     // 3 → −1
    EXPECT_NEAR(at_tau(11).pressure, 2.5 * bar.stress, 1e-12 * bar.stress);  // 0 → 5
    EXPECT_NEAR(at_tau(13).velocity, 1.5 * bar.speed, 1e-12 * bar.speed);    // 0 → 3
    EXPECT_NEAR(exact.at((7 + 2e-9) * bar.transit, tolerance).velocity, -1.0 * bar.speed,
                1e-8 * bar.speed);
  }
}

// The motion repeats every 16L/c: after the second contact the bar is rigid and unstressed
// again, and lands at 19L/c as it did at 3L/c; between the contacts it vibrates.
TEST(BouncingBarExact, PeriodSixteenTransits) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double length = bar.params.length, period = 16.0 * bar.transit;
    EXPECT_DOUBLE_EQ(exact.period(), period);
    std::mt19937 random(13);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
      const double x = length * unit(random), t = period * unit(random);
      for (int k = 1; k <= 3; ++k) {
        EXPECT_NEAR(exact.displacement(x, t + k * period), exact.displacement(x, t),
                    1e-12 * 128 * bar.length)
            << "x = " << x << ", t = " << t << ", k = " << k;
      }
    }
    double largest_flight_stress = 0.0;
    for (int i = 0; i <= 50; ++i) {
      const double x = node(i, 50, length);
      // Just before 16L/c: back at the release position, at rest.
      const BarPointValues end = exact.point(x, period * (1.0 - 1e-10), 0.0);
      EXPECT_NEAR(end.displacement, 0.0, 1e-12 * 128 * bar.length) << x;
      EXPECT_NEAR(end.velocity, 0.0, 1e-8 * bar.speed) << x;
      // Rigid and unstressed between the second contact and the apex, at (16 − τ)·gD.
      for (const double tau : {13.5, 14.5, 15.5}) {
        const BarPointValues rigid = exact.point(x, tau * bar.transit, 0.0);
        EXPECT_EQ(rigid.stress, 0.0) << x;
        EXPECT_NEAR(rigid.velocity, (16.0 - tau) * bar.speed, 1e-12 * 16 * bar.speed) << x;
      }
      // Landing at 3L/c and 19L/c at −3gD, unstressed.
      for (const double tau : {3.0 - 1e-7, 19.0 - 1e-7}) {
        const BarPointValues landing = exact.point(x, tau * bar.transit, 0.0);
        EXPECT_NEAR(landing.velocity, -3.0 * bar.speed, 1e-6 * bar.speed) << x;
        EXPECT_EQ(landing.stress, 0.0) << x;
      }
      for (const double tau : {6.0, 8.0, 10.0}) {
        largest_flight_stress = std::max(largest_flight_stress,
                                         std::abs(exact.point(x, tau * bar.transit, 0.0).stress));
      }
    }
    EXPECT_GT(largest_flight_stress, 0.5 * bar.stress);  // the vibration between the contacts
    // Not a shorter period: half a period later the lower end is elsewhere.
    EXPECT_GT(std::abs(exact.displacement(0.0, 0.0) - exact.displacement(0.0, 0.5 * period)),
              0.1 * bar.gap);
  }
}

// Kinetic + strain + gravitational energy, ρgL·(d + L/2) at all times: from the class's exact
// integration, and from this test's own quadrature of finite differences of the displacement.
TEST(BouncingBarExact, EnergyIsConserved) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double length = bar.params.length, rho = bar.params.density;
    const double g = bar.params.gravity, E = bar.params.youngs_modulus;
    EXPECT_DOUBLE_EQ(exact.energy_constant(), bar.energy);
    for (int i = 0; i <= 800; ++i) {
      const double t = 32.0 * bar.transit * i / 800.0 + 1e-3 * bar.transit;
      EXPECT_NEAR(exact.energy(t), bar.energy, 1e-12 * bar.energy) << t;
    }
    // The mechanical part alone is what moves: 9ρL·(gD)²/2 at the landing.
    const double motion = 4.5 * rho * length * bar.speed * bar.speed;
    for (const double tau : {0.0, 1.7, 3.0, 4.2, 5.5, 6.3, 8.0, 9.9, 11.4, 12.8, 14.1, 21.0}) {
      const double t = tau * bar.transit;
      const int n = 20000;
      const double hx = length / n, ht = 1e-6 * bar.transit;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) * hx;
        const double strain = (exact.displacement(node(i + 1, n, length), t) -
                               exact.displacement(node(i, n, length), t)) /
                              hx;
        const double velocity =
            (exact.displacement(x, t + ht) - exact.displacement(x, t - ht)) / (2 * ht);
        sum += 0.5 * rho * velocity * velocity + 0.5 * E * strain * strain +
               rho * g * (bar.gap + x + exact.displacement(x, t));
      }
      EXPECT_NEAR(sum * hx, bar.energy, 2e-3 * motion) << "t = " << t;
    }
  }
}

// Two episodes per period, [3, 5] and [11, 13] (in L/c) + 16k, each with impulse 8ρgL·D:
// against the integral of the pressure, and against the momentum balance
// dP/dt = p(t) − ρgL with P = ρ·d/dt ∫u dx from finite differences of the displacement.
TEST(BouncingBarExact, EpisodesAndImpulses) {
  for (const Bar& bar : bars()) {
    const BouncingBarExact exact(bar.params);
    const double D = bar.transit, rho = bar.params.density, length = bar.params.length;
    const double impulse = 8.0 * bar.stress * D;
    const std::vector<ContactEpisode> episodes = exact.episodes(40.0 * D);
    ASSERT_EQ(episodes.size(), 5u);
    const double starts[] = {3, 11, 19, 27, 35};
    for (std::size_t k = 0; k < episodes.size(); ++k) {
      const ContactEpisode& e = episodes[k];
      EXPECT_NEAR(e.start, starts[k] * D, 1e-12 * 40 * D) << k;
      EXPECT_NEAR(e.end, (starts[k] + 2) * D, 1e-12 * 40 * D) << k;
      EXPECT_NEAR(e.impulse, impulse, 1e-12 * impulse) << k;

      const int n = 1000;  // the midpoint rule, exact for the linear pressure
      const double dt = (e.end - e.start) / n;
      double pressure_integral = 0.0;
      for (int i = 0; i < n; ++i)
        pressure_integral += dt * exact.at(e.start + (i + 0.5) * dt, 0.0).pressure;
      EXPECT_NEAR(pressure_integral, e.impulse, 1e-9 * impulse) << k;

      const auto momentum = [&](double t) {
        const double h = 1e-6 * D;
        return rho *
               (displacement_integral(exact, bar, t + h) -
                displacement_integral(exact, bar, t - h)) /
               (2 * h);
      };
      const double gained = momentum(e.end) - momentum(e.start);
      EXPECT_NEAR(gained, e.impulse - bar.stress * (e.end - e.start), 1e-4 * impulse) << k;
      EXPECT_NEAR(gained, 6.0 * rho * length * bar.speed, 1e-4 * impulse) << k;  // −3gD to +3gD
    }
    // Episodes still open at t_end end there, with the impulse so far.
    const ContactEpisode rising = exact.episodes(36.0 * D).back();
    EXPECT_NEAR(rising.end, 36.0 * D, 1e-12 * 36 * D);
    EXPECT_NEAR(rising.impulse, 3.5 * bar.stress * D, 1e-12 * impulse);  // ∫₃⁴ τ dτ
    const ContactEpisode falling = exact.episodes(12.0 * D).back();
    EXPECT_NEAR(falling.impulse, 4.5 * bar.stress * D, 1e-12 * impulse);  // ∫₁₁¹² (16 − τ) dτ
  }
}

TEST(BouncingBarExact, RejectsInvalidParameters) {
  EXPECT_FALSE(validate(BouncingBarParams{}));
  const auto error = validate(BouncingBarParams{.gravity = -10.0});
  ASSERT_TRUE(error);
  EXPECT_EQ(error->field, "gravity");
  EXPECT_EQ(error->value, "-10");
  EXPECT_EQ(validate(BouncingBarParams{.length = 0.0})->field, "length");
  EXPECT_EQ(validate(BouncingBarParams{.youngs_modulus = -1.0})->field, "youngs_modulus");
  EXPECT_EQ(validate(BouncingBarParams{.density = std::nan("")})->field, "density");
  EXPECT_TRUE(validate(BouncingBarParams{.youngs_modulus = 1e-300, .density = 1e300}));
  EXPECT_THROW(BouncingBarExact(BouncingBarParams{.gravity = 0.0}), std::invalid_argument);

  const BouncingBarExact exact;
  EXPECT_THROW(exact.displacement(10.0 + 1e-9, 0.0), std::out_of_range);
  EXPECT_THROW(exact.point(-1e-9, 0.0, 0.0), std::out_of_range);
  EXPECT_THROW(exact.episodes(-1.0), std::invalid_argument);
  EXPECT_TRUE(exact.episodes(0.9).empty());  // the first impact is at t = 1
}

}  // namespace
}  // namespace impactid
