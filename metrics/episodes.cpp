#include "metrics/episodes.hpp"

#include <cassert>
#include <cmath>
#include <limits>

#include "metrics/peak_count.hpp"

namespace impactid {

namespace {

struct Run {
  std::size_t first, last;  // sample indices, inclusive
};

// The maximal runs of samples with p > 0.
std::vector<Run> contact_runs(std::span<const double> p) {
  std::vector<Run> runs;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!(p[i] > 0.0)) continue;
    if (!runs.empty() && runs.back().last + 1 == i) {
      runs.back().last = i;
    } else {
      runs.push_back({i, i});
    }
  }
  return runs;
}

}  // namespace

std::vector<EpisodeComparison> compare_episodes(std::span<const double> reference,
                                                std::span<const double> pressure, double dt,
                                                double min_prominence,
                                                std::span<const double> energy,
                                                double initial_energy) {
  assert(reference.size() == pressure.size());
  assert(energy.empty() || energy.size() == pressure.size());
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Run> episodes = contact_runs(reference);
  const auto time = [dt](std::size_t i) { return static_cast<double>(i + 1) * dt; };
  std::vector<EpisodeComparison> out(episodes.size());
  std::size_t window_begin = 0;
  for (std::size_t k = 0; k < episodes.size(); ++k) {
    // The window ends in the middle of the gap to the next episode (at the last sample).
    const std::size_t window_end = k + 1 < episodes.size()
                                       ? (episodes[k].last + episodes[k + 1].first) / 2
                                       : pressure.size() - 1;
    EpisodeComparison& e = out[k];
    e.reference_start = time(episodes[k].first);
    e.reference_end = time(episodes[k].last);
    e.start = e.end = kNaN;
    bool in_contact = false;
    for (std::size_t i = window_begin; i <= window_end; ++i) {
      e.reference_impulse += reference[i] * dt;
      e.impulse += pressure[i] * dt;
      const bool active = pressure[i] > 0.0;
      if (active) {
        if (!in_contact) ++e.contact_runs;
        if (std::isnan(e.start)) e.start = time(i);
        e.end = time(i);
      }
      in_contact = active;
    }
    e.energy_ratio = !energy.empty() && initial_energy > 0.0
                         ? energy[window_end] / initial_energy
                         : kNaN;
    window_begin = window_end + 1;
  }
  // The peaks by NoP_p's rule over the whole run, each to the window where its drop completes.
  PeakCounter counter(min_prominence);
  std::size_t k = 0;
  for (std::size_t i = 0; i < pressure.size() && !out.empty(); ++i) {
    const long before = counter.peaks();
    counter.add(pressure[i]);
    while (k + 1 < episodes.size() && i > (episodes[k].last + episodes[k + 1].first) / 2) ++k;
    out[k].peaks += counter.peaks() - before;
  }
  return out;
}

}  // namespace impactid
