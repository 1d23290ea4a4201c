// The clamped bar released onto an obstacle (Doyen, Ern & Piperno 2011), against its own
// invariants and closed forms, computed here from the problem's statement rather than from the
// class: the wave equation by finite differences of the displacement, the clamp and the Signorini
// conditions, the initial data, the period 3L/c, the energy a²E/(2L) and each episode's impulse
// against the momentum the bar gains over it. Each test runs on the benchmark (L = E = ρ = 1,
// a = ½) and on a scaled bar.
#include "core/reference/clamped_bar_exact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace impactid {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// What the tests know of a bar, worked out from its parameters only.
struct Bar {
  ClampedBarParams params;
  double c, transit, period, speed, pressure, energy;  // c, L/c, 3L/c, ac/L, aE/L, a²E/(2L)
};
Bar bar_of(const ClampedBarParams& p) {
  const double c = std::sqrt(p.youngs_modulus / p.density);
  return {p,
          c,
          p.length / c,
          3.0 * p.length / c,
          p.amplitude * c / p.length,
          p.amplitude * p.youngs_modulus / p.length,
          p.amplitude * p.amplitude * p.youngs_modulus / (2.0 * p.length)};
}
std::vector<Bar> bars() {
  return {bar_of(ClampedBarParams{}),
          bar_of(ClampedBarParams{
              .length = 2.5, .youngs_modulus = 210.0, .density = 7.8, .amplitude = 0.03})};
}

// The characteristics through the kinks, by the derivation: the end's w+ changes at
// ct/L − x/L ≡ 0 or 1 (mod 3), the clamp's w− at ct/L + x/L ≡ 2 or 0 (mod 3). Distance of
// (x, t) to the nearest of them, in units of L/c.
double kink_distance(const Bar& bar, double x, double t) {
  const double tau = t / bar.transit, xi = x / bar.params.length;
  double nearest = std::numeric_limits<double>::infinity();
  for (const double s : {tau - xi, tau + xi - 2.0}) {
    const double r = s - 3.0 * std::floor(s / 3.0);
    for (const double jump : {0.0, 1.0, 3.0}) nearest = std::min(nearest, std::abs(r - jump));
  }
  return nearest;
}

// ∫ u(x, t) dx by the midpoint rule. Its error in a cell crossed by a kink at δ from the cell's
// edge is O(δ²), so the momentum it gives at a time when the kinks sit on the ends is exact to
// O(h) (the trapezoid rule's error there moves linearly with the kink: O(1/n) in the momentum).
double displacement_integral(const ClampedBarExact& exact, const Bar& bar, double t) {
  const int n = 4000;
  const double h = bar.params.length / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += exact.displacement((i + 0.5) * h, t);
  return sum * h;
}

// The initial data: u(x, 0) = a·(1 − x/L), at rest, uniformly compressed by aE/L.
TEST(ClampedBarExact, InitialData) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double a = bar.params.amplitude, length = bar.params.length;
    for (int i = 0; i <= 100; ++i) {
      const double x = length * i / 100.0;
      EXPECT_NEAR(exact.displacement(x, 0.0), a * (1.0 - x / length), 4 * kEps * a) << x;
      if (i == 0 || i == 100) continue;  // the release front starts from x = 0
      const BarPointValues value = exact.point(x, 0.0, 0.0);
      EXPECT_EQ(value.velocity, 0.0) << x;
      EXPECT_DOUBLE_EQ(value.stress, -bar.pressure) << x;
    }
  }
}

// u_tt = c²·u_xx: the diamond of characteristics u(x, t+h) + u(x, t−h) − u(x+ch, t) − u(x−ch, t)
// vanishes for every diamond inside the bar, kinks or not; and away from the kinks, where the
// solution is linear in x and t, both second differences vanish on their own.
TEST(ClampedBarExact, WaveEquation) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double a = bar.params.amplitude, length = bar.params.length;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
      const double x = length * (0.05 + 0.9 * unit(random));
      const double t = 2.5 * bar.period * unit(random);
      const double reach = 0.99 * std::min(x, length - x) * unit(random);
      const double h = reach / bar.c;
      const double diamond = exact.displacement(x, t + h) + exact.displacement(x, t - h) -
                             exact.displacement(x + reach, t) - exact.displacement(x - reach, t);
      EXPECT_NEAR(diamond, 0.0, 64 * kEps * a) << "x = " << x << ", t = " << t << ", h = " << h;
    }
    int smooth = 0;
    for (int i = 0; i < 4000; ++i) {
      const double x = length * (0.05 + 0.9 * unit(random));
      const double t = 2.5 * bar.period * unit(random);
      const double ht = 1e-3 * bar.transit, hx = 0.7e-3 * length;  // not on the characteristics
      if (kink_distance(bar, x, t) < 3e-3) continue;
      ++smooth;
      const double u = exact.displacement(x, t);
      const double utt = exact.displacement(x, t + ht) - 2 * u + exact.displacement(x, t - ht);
      const double uxx = exact.displacement(x + hx, t) - 2 * u + exact.displacement(x - hx, t);
      EXPECT_NEAR(utt, 0.0, 64 * kEps * a) << "x = " << x << ", t = " << t;
      EXPECT_NEAR(uxx, 0.0, 64 * kEps * a) << "x = " << x << ", t = " << t;
    }
    EXPECT_GT(smooth, 3000);
  }
}

// The clamp holds, the obstacle is never penetrated, the pressure pushes, and the two are
// complementary; the contact end's pressure and velocity are those of the displacement field.
TEST(ClampedBarExact, BoundaryAndSignoriniConditions) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double a = bar.params.amplitude, length = bar.params.length, tol = 8 * kEps * a;
    int held = 0, free = 0;
    for (int i = 0; i <= 6000; ++i) {
      const double t = 2.0 * bar.period * i / 6000.0;
      EXPECT_NEAR(exact.displacement(length, t), 0.0, 4 * kEps * a) << t;
      const ContactNodeValues end = exact.at(t, 0.0);
      EXPECT_GE(end.displacement, -tol) << t;
      EXPECT_GE(end.pressure, 0.0) << t;
      if (end.displacement > tol) {
        EXPECT_EQ(end.pressure, 0.0) << t;
      }
      if (end.pressure > 0.0) {
        EXPECT_LE(std::abs(end.displacement), tol) << t;
      }
      const double tau = std::fmod(t / bar.transit, 3.0);
      if (std::abs(tau - 1.0) > 1e-9 && std::abs(tau - 2.0) > 1e-9) {
        EXPECT_EQ(exact.in_contact(t), std::abs(end.displacement) <= tol) << t;
      }
      if (kink_distance(bar, 0.0, t) < 2e-3) continue;  // finite differences across a jump
      // p = −E·u_x(0, t) and v = u_t(0, t) by one-sided and central differences.
      const double hx = 1e-3 * length, ht = 1e-3 * bar.transit;
      const double strain = (exact.displacement(hx, t) - exact.displacement(0.0, t)) / hx;
      const double rate =
          (exact.displacement(0.0, t + ht) - exact.displacement(0.0, t - ht)) / (2 * ht);
      EXPECT_NEAR(end.pressure, -bar.params.youngs_modulus * strain, 1e-9 * bar.pressure) << t;
      EXPECT_NEAR(end.velocity, rate, 1e-9 * bar.speed) << t;
      (end.pressure > 0.0 ? held : free) += 1;
    }
    EXPECT_GT(held, 1000);
    EXPECT_GT(free, 2000);
  }
}

// The contact end phase by phase (τ = ct/L mod 3): free toward the obstacle, held at aE/L, free
// away from it; on a jump within the tolerance the mean of both sides, outside it one side.
TEST(ClampedBarExact, ContactEndByPhase) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double a = bar.params.amplitude;
    for (int period = 0; period < 3; ++period) {
      for (int i = 1; i < 300; ++i) {
        const double tau = 3.0 * i / 300.0;
        if (std::abs(tau - 1.0) < 1e-9 || std::abs(tau - 2.0) < 1e-9) continue;
        const double t = (tau + 3.0 * period) * bar.transit;
        const ContactNodeValues end = exact.at(t, 0.0);
        const double p = tau < 1.0 || tau > 2.0 ? 0.0 : bar.pressure;
        const double v = tau < 1.0 ? -bar.speed : (tau < 2.0 ? 0.0 : bar.speed);
        const double u = tau < 1.0 ? a * (1.0 - tau) : (tau < 2.0 ? 0.0 : a * (tau - 2.0));
        EXPECT_DOUBLE_EQ(end.pressure, p) << t;
        EXPECT_NEAR(end.velocity, v, 1e-12 * bar.speed) << t;
        EXPECT_NEAR(end.displacement, u, 1e-12 * a * (period + 1)) << t;
      }
    }
    const double tolerance = 1e-9 * bar.transit;
    const ContactNodeValues impact = exact.at(bar.transit + 0.5 * tolerance, tolerance);
    EXPECT_DOUBLE_EQ(impact.pressure, 0.5 * bar.pressure);
    EXPECT_DOUBLE_EQ(impact.velocity, -0.5 * bar.speed);
    const ContactNodeValues release = exact.at(2.0 * bar.transit, tolerance);
    EXPECT_DOUBLE_EQ(release.pressure, 0.5 * bar.pressure);
    EXPECT_DOUBLE_EQ(release.velocity, 0.5 * bar.speed);
    const ContactNodeValues after = exact.at(2.0 * bar.transit + 2.0 * tolerance, tolerance);
    EXPECT_EQ(after.pressure, 0.0);
    EXPECT_DOUBLE_EQ(after.velocity, bar.speed);
  }
}

// The motion repeats every 3L/c, and the end of a period joins its beginning.
TEST(ClampedBarExact, PeriodThreeTransits) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double a = bar.params.amplitude, length = bar.params.length;
    EXPECT_DOUBLE_EQ(exact.period(), bar.period);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 1000; ++i) {
      const double x = length * unit(random), t = bar.period * unit(random);
      for (int k = 1; k <= 4; ++k) {
        EXPECT_NEAR(exact.displacement(x, t + k * bar.period), exact.displacement(x, t),
                    64 * kEps * a)
            << "x = " << x << ", t = " << t << ", k = " << k;
      }
    }
    // Just before t = 3L/c the bar is back at its initial compression, at rest.
    const double before = bar.period * (1.0 - 1e-9);
    for (int i = 1; i < 100; ++i) {
      const double x = length * i / 100.0;
      EXPECT_NEAR(exact.displacement(x, before), a * (1.0 - x / length), 1e-8 * a) << x;
      EXPECT_EQ(exact.point(x, before, 0.0).velocity, 0.0) << x;
    }
    // Not a shorter period: half a period later the contact end is elsewhere.
    EXPECT_GT(std::abs(exact.displacement(0.0, 0.0) - exact.displacement(0.0, 0.5 * bar.period)),
              0.1 * a);
  }
}

// The energy is a²E/(2L) at all times: from the class's exact integration, and from this test's
// own quadrature of finite differences of the displacement.
TEST(ClampedBarExact, EnergyIsConserved) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double length = bar.params.length;
    for (int i = 0; i <= 600; ++i) {
      const double t = 2.0 * bar.period * i / 600.0 + 1e-3 * bar.transit;
      EXPECT_NEAR(exact.energy(t), bar.energy, 1e-12 * bar.energy) << t;
    }
    for (const double tau : {0.0, 0.3, 1.0, 1.45, 2.2, 2.9, 4.6, 8.1}) {
      const double t = tau * bar.transit;
      const int n = 4000;
      const double hx = length / n, ht = 1e-7 * bar.transit;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) * hx;
        const double right = i + 1 == n ? length : (i + 1) * hx;
        const double strain = (exact.displacement(right, t) - exact.displacement(i * hx, t)) / hx;
        const double velocity =
            (exact.displacement(x, t + ht) - exact.displacement(x, t - ht)) / (2 * ht);
        sum += 0.5 * bar.params.density * velocity * velocity +
               0.5 * bar.params.youngs_modulus * strain * strain;
      }
      EXPECT_NEAR(sum * hx, bar.energy, 2e-3 * bar.energy) << "t = " << t;
    }
  }
}

// One episode per period, [L/c, 2L/c] + 3kL/c, with impulse a·ρc: against the integral of the
// pressure, and against the momentum balance dP/dt = σ(L, t) + p(t) (the clamp pulls too), with
// P = ρ·d/dt ∫u dx and σ(L, t) = E·u_x(L, t) from finite differences of the displacement.
TEST(ClampedBarExact, EpisodesAndImpulses) {
  for (const Bar& bar : bars()) {
    const ClampedBarExact exact(bar.params);
    const double length = bar.params.length, rho = bar.params.density;
    const double t_end = 3.5 * bar.period;  // ends inside the fourth episode
    const std::vector<ContactEpisode> episodes = exact.episodes(t_end);
    ASSERT_EQ(episodes.size(), 4u);
    const double impulse = bar.params.amplitude * rho * bar.c;
    for (std::size_t k = 0; k < episodes.size(); ++k) {
      const ContactEpisode& e = episodes[k];
      EXPECT_NEAR(e.start, (3.0 * k + 1.0) * bar.transit, 1e-12 * bar.period) << k;
      if (k == 3) {
        EXPECT_EQ(e.end, t_end);
        EXPECT_NEAR(e.impulse, impulse * (t_end - e.start) / bar.transit, 1e-12 * impulse);
        continue;
      }
      EXPECT_NEAR(e.end, (3.0 * k + 2.0) * bar.transit, 1e-12 * bar.period) << k;
      EXPECT_NEAR(e.impulse, impulse, 1e-12 * impulse) << k;

      // ∫ p dt and ∫ σ(L, t) dt by the midpoint rule over the episode (both are constant in it).
      const int n = 1000;
      const double dt = (e.end - e.start) / n;
      double pressure_integral = 0.0, clamp_integral = 0.0;
      for (int i = 0; i < n; ++i) {
        const double t = e.start + (i + 0.5) * dt, hx = 1e-6 * length;
        pressure_integral += dt * exact.at(t, 0.0).pressure;
        clamp_integral += dt * bar.params.youngs_modulus *
                          (exact.displacement(length, t) - exact.displacement(length - hx, t)) / hx;
      }
      EXPECT_NEAR(pressure_integral, e.impulse, 1e-9 * impulse) << k;

      const auto momentum = [&](double t) {
        const double h = 1e-6 * bar.transit;
        return rho *
               (displacement_integral(exact, bar, t + h) -
                displacement_integral(exact, bar, t - h)) /
               (2 * h);
      };
      const double gained = momentum(e.end) - momentum(e.start);
      EXPECT_NEAR(gained, e.impulse + clamp_integral, 1e-4 * impulse) << k;
      EXPECT_NEAR(gained, 2.0 * rho * bar.speed * length, 1e-4 * impulse) << k;  // −V to +V
    }
  }
}

TEST(ClampedBarExact, RejectsInvalidParameters) {
  EXPECT_FALSE(validate(ClampedBarParams{}));
  const auto error = validate(ClampedBarParams{.amplitude = 0.0});
  ASSERT_TRUE(error);
  EXPECT_EQ(error->field, "amplitude");
  EXPECT_EQ(error->value, "0");
  EXPECT_EQ(validate(ClampedBarParams{.length = -1.0})->field, "length");
  EXPECT_EQ(validate(ClampedBarParams{.youngs_modulus = std::nan("")})->field, "youngs_modulus");
  EXPECT_EQ(validate(ClampedBarParams{.density = 0.0})->field, "density");
  EXPECT_TRUE(validate(ClampedBarParams{.youngs_modulus = 1e300, .density = 1e-300}));
  EXPECT_THROW(ClampedBarExact(ClampedBarParams{.density = -2.0}), std::invalid_argument);

  const ClampedBarExact exact;
  EXPECT_THROW(exact.displacement(1.0 + 1e-12, 0.0), std::out_of_range);
  EXPECT_THROW(exact.point(-1e-12, 0.0, 0.0), std::out_of_range);
  EXPECT_THROW(exact.episodes(-1.0), std::invalid_argument);
  EXPECT_THROW(exact.episodes(std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_TRUE(exact.episodes(0.5).empty());
}

}  // namespace
}  // namespace impactid
