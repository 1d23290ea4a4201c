// The contact episodes of a run beside its reference's (metrics/episodes.hpp): the windows'
// rule on hand-made signals, then on runs against closed forms: the clamped bar's two contacts of
// two periods (each from t = 1 to 2 pressing with 1/2: impulse 1/2), and the paper's rod's one
// contact (duration 2L/c at ρ·c·v0: impulse 2ρ·L·v0). The peaks given to the episodes add up to
// the run's NoP_p.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "metrics/episodes.hpp"
#include "metrics/peak_count.hpp"
#include "study/studies/evaluation.hpp"

namespace impactid {
namespace {

TEST(Episodes, AnIdenticalRunMatchesItsReference) {
  const std::vector<double> p{0, 0, 1, 1, 0, 0, 0, 2, 3, 2, 0};
  const auto e = compare_episodes(p, p, 0.5, 1e-9);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[0].reference_start, 1.5);  // sample 2 is t = 3·Δt
  EXPECT_DOUBLE_EQ(e[0].reference_end, 2.0);
  EXPECT_DOUBLE_EQ(e[1].reference_start, 4.0);
  EXPECT_DOUBLE_EQ(e[1].reference_end, 5.0);
  for (const EpisodeComparison& c : e) {
    EXPECT_EQ(c.start, c.reference_start);
    EXPECT_EQ(c.end, c.reference_end);
    EXPECT_EQ(c.impulse, c.reference_impulse);
    EXPECT_EQ(c.contact_runs, 1);
    EXPECT_EQ(c.peaks, 1);
    EXPECT_TRUE(std::isnan(c.energy_ratio));
  }
  EXPECT_DOUBLE_EQ(e[0].reference_impulse, 1.0);  // (1 + 1)·0.5
  EXPECT_DOUBLE_EQ(e[1].reference_impulse, 3.5);  // (2 + 3 + 2)·0.5
}

TEST(Episodes, TheWindowsSplitTheGapsInTheMiddle) {
  // Reference episodes at samples 2..3 and 7..9: the gap 4..6 splits after sample 5.
  const std::vector<double> reference{0, 0, 1, 1, 0, 0, 0, 1, 1, 1, 0};
  std::vector<double> run{0, 0, 0, 1, 0, 1, 1, 1, 1, 0, 0};
  const auto e = compare_episodes(reference, run, 1.0, 1e-9);
  ASSERT_EQ(e.size(), 2u);
  // Window 0 (samples 0..5): a late start at sample 3, then a lone contact at 5 (chatter).
  EXPECT_EQ(e[0].start, 4.0);
  EXPECT_EQ(e[0].end, 6.0);
  EXPECT_EQ(e[0].contact_runs, 2);
  EXPECT_EQ(e[0].impulse, 2.0);
  // Window 1 (samples 6..10): an early start at sample 6, an early end at 8.
  EXPECT_EQ(e[1].start, 7.0);
  EXPECT_EQ(e[1].end, 9.0);
  EXPECT_EQ(e[1].contact_runs, 1);
  EXPECT_EQ(e[1].impulse, 3.0);
  EXPECT_EQ(e[1].reference_impulse, 3.0);
}

TEST(Episodes, ARunWithoutContactInItsWindowHasNoStartOrEnd) {
  const std::vector<double> reference{0, 1, 1, 0};
  const std::vector<double> run{0, 0, 0, 0};
  const auto e = compare_episodes(reference, run, 1.0, 1e-9);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_TRUE(std::isnan(e[0].start));
  EXPECT_TRUE(std::isnan(e[0].end));
  EXPECT_EQ(e[0].impulse, 0.0);
  EXPECT_EQ(e[0].contact_runs, 0);
}

TEST(Episodes, NoReferenceContactGivesNoEpisodes) {
  const std::vector<double> reference(5, 0.0);
  const std::vector<double> run{0, 1, 0, 1, 0};
  EXPECT_TRUE(compare_episodes(reference, run, 1.0, 1e-9).empty());
}

TEST(Episodes, TheEnergyIsTakenAtTheWindowsEnd) {
  const std::vector<double> reference{0, 1, 0, 0, 1, 0};
  const std::vector<double> energy{4, 4, 3, 3, 2, 1};
  const auto e = compare_episodes(reference, reference, 1.0, 1e-9, energy, 4.0);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].energy_ratio, 3.0 / 4.0);  // window 0 ends at sample (1 + 4)/2 = 2
  EXPECT_EQ(e[1].energy_ratio, 1.0 / 4.0);  // the last window ends at the last sample
}

TEST(Episodes, ThePeaksOfTheEpisodesAddUpToTheRunsCount) {
  std::vector<double> reference(400, 0.0), run(400, 0.0);
  for (int i = 0; i < 400; ++i) {
    const bool contact = (i >= 50 && i < 120) || (i >= 200 && i < 260) || (i >= 330 && i < 390);
    reference[static_cast<std::size_t>(i)] = contact ? 1.0 : 0.0;
    run[static_cast<std::size_t>(i)] =
        contact ? 1.0 + 0.3 * std::sin(0.7 * i) : std::max(0.0, 0.2 * std::sin(0.9 * i));
  }
  PeakCounter all(0.01);
  for (const double v : run) all.add(v);
  long sum = 0;
  for (const EpisodeComparison& c : compare_episodes(reference, run, 1.0, 0.01)) sum += c.peaks;
  EXPECT_EQ(sum, all.peaks());
  EXPECT_GT(sum, 30);
}

// The clamped bar of Doyen, Ern & Piperno on 100 elements at Courant 1 over two periods:
// contact from t = 1 to 2 and from 4 to 5, pressing with 1/2 (core/reference/clamped_bar_exact.hpp).
Simulation clamped_bar(const MethodParams& method) {
  Scene s;
  s.bodies.push_back(Body{
      .name = "bar",
      .segments = {Segment{.length = 1.0, .elements = 100, .youngs_modulus = 1.0, .density = 1.0}},
      .displacement = {.left = 0.5, .right = 0.0}});
  s.left_wall = Wall{.gap = 0.0};
  s.right_wall = Wall{.kind = WallKind::clamped};
  s.courant = 1.0;
  s.t_end = 6.0;
  return Simulation{.scene = s, .method = method};
}

TEST(Episodes, TheClampedBarsTwoContactsAgainstTheirClosedForm) {
  const Simulation sim = clamped_bar(CentralDifferenceParams{});
  SimulationWorkspace ws;
  const Evaluation e = evaluate(sim, ws);
  ASSERT_EQ(e.summary.status, RunStatus::ok);
  const auto episodes = primary_episodes(sim, ws, e.summary);
  ASSERT_EQ(episodes.size(), 2u);
  const double dt = e.summary.dt;
  for (std::size_t k = 0; k < 2; ++k) {
    const EpisodeComparison& c = episodes[k];
    const double start = 1.0 + 3.0 * static_cast<double>(k);
    EXPECT_NEAR(c.reference_start, start, 1.01 * dt) << k;
    EXPECT_NEAR(c.reference_end, start + 1.0, 1.01 * dt) << k;
    EXPECT_NEAR(c.reference_impulse, 0.5, 0.5 * 2.01 * dt) << k;
    // Central difference at Courant 1 is exact off the jumps: the same contact to a step.
    EXPECT_NEAR(c.start, c.reference_start, 1.01 * dt) << k;
    EXPECT_NEAR(c.end, c.reference_end, 1.01 * dt) << k;
    EXPECT_NEAR(c.impulse, c.reference_impulse, 0.02 * c.reference_impulse) << k;
  }
}

TEST(Episodes, TheRodsOneContactAndItsPeaks) {
  const RodScene rod;
  const Simulation sim{.scene = rod, .method = HhtParams{.alpha = -0.3}};
  SimulationWorkspace ws;
  Simulation with_history = sim;
  with_history.run.record_history = true;
  const Evaluation e = evaluate(with_history, ws);
  ASSERT_EQ(e.summary.status, RunStatus::ok);
  const auto episodes = primary_episodes(with_history, ws, e.summary);
  ASSERT_EQ(episodes.size(), 1u);
  const RodSceneDerived d = derive(rod);
  const EpisodeComparison& c = episodes[0];
  const double duration = 2.0 * rod.length / d.wave_speed;
  EXPECT_NEAR(c.reference_start, rod.gap / rod.velocity, 1.01 * d.time_step);
  EXPECT_NEAR(c.reference_end - c.reference_start, duration, 2.01 * d.time_step);
  const double impulse = 2.0 * rod.density * rod.length * rod.velocity;  // ρ·c·v0 · 2L/c
  EXPECT_NEAR(c.reference_impulse, impulse, 2.01 * d.time_step * d.pressure_scale);
  EXPECT_NEAR(c.impulse, impulse, 0.05 * impulse);
  EXPECT_EQ(static_cast<double>(c.peaks), e.indicators.nop_p);
  // HHT dissipates: the energy after the contact is below the initial one, and positive.
  EXPECT_GT(c.energy_ratio, 0.0);
  EXPECT_LT(c.energy_ratio, 1.0);
}

}  // namespace
}  // namespace impactid
