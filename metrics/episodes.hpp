// A run's contact episodes set beside its reference's, one by one: when each contact starts and
// ends, the impulse it carries, how many peaks its pressure has and what energy is left after it
// (issue 36's long-time indicators, as Doyen, Ern & Piperno 2011 and GetFEM's
// demo_dynamic_contact_1D report a multi-impact run). `impactid simulate` prints them.
//
// The rule, at the samples t_i = (i + 1)·Δt of a contact's pressure:
// - the reference's episodes are its maximal runs of samples with p > 0 (the rule of
//   contact_episodes, metrics/indicators.hpp);
// - each reference episode owns a window of samples: from the middle of the gap before it to the
//   middle of the gap after it (the first window starts at the first sample, the last ends at the
//   last), so the windows partition the run and whatever the run does near an episode, a late
//   start, chatter, a lingering contact, is measured against that episode;
// - in its window the run's episode starts at its first sample with p > 0 and ends at its last
//   (NaN when it has none); its impulse is Σ p_i·Δt over the window (pressure × time: the force
//   impulse per unit area); `contact_runs` counts its maximal runs of p > 0 (1 for a clean
//   contact, more when it chatters);
// - peaks are counted over the whole run by the rule of NoP_p (metrics/peak_count.hpp, the same
//   prominence), each given to the window in which its drop completes, so the episodes' peaks add
//   up to NoP_p;
// - the energy after an episode is the run's energy at its window's last sample over the initial
//   energy, when the run recorded its energies (a run with histories); NaN otherwise.
// Without a reference episode (no contact in the reference) there is no window: the list is empty.
#pragma once

#include <span>
#include <vector>

namespace impactid {

struct EpisodeComparison {
  double start = 0.0, reference_start = 0.0;  ///< first sample time with p > 0 [s]
  double end = 0.0, reference_end = 0.0;      ///< last sample time with p > 0 [s]
  double impulse = 0.0, reference_impulse = 0.0;  ///< Σ p·Δt over the window [pressure·s]
  long peaks = 0;             ///< the run's pressure peaks given to this window
  long contact_runs = 0;      ///< the run's maximal runs of samples with p > 0 in the window
  double energy_ratio = 0.0;  ///< energy at the window's end / initial energy, or NaN
};

/// The episodes of `pressure` against those of `reference` (the same samples), with time step
/// `dt` and the peak rule's `min_prominence`; `energy` the run's energy at each sample (empty when
/// not recorded) and `initial_energy` its start's.
std::vector<EpisodeComparison> compare_episodes(std::span<const double> reference,
                                                std::span<const double> pressure, double dt,
                                                double min_prominence,
                                                std::span<const double> energy = {},
                                                double initial_energy = 0.0);

}  // namespace impactid
