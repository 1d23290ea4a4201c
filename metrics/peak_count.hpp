// The number of peaks NoP of a sampled signal (paper sec. 4, the count of spurious
// oscillations), by this rule:
//   - a peak is a local maximum: a sample, or a run of exactly equal samples (a flat top, counted
//     once), whose neighbours on both sides are strictly lower; the first and last samples are
//     never peaks (the rule of scipy.signal.find_peaks);
//   - it counts only if its topographic prominence is at least `min_prominence`. The prominence
//     is the height of the peak above the higher of its two bases, each base being the lowest
//     sample between the peak and the nearest higher sample on that side (or the end of the
//     signal): strictly higher on the right, higher or equal on the left. That is
//     scipy.signal.peak_prominences except for ties: of two equal summits the earlier is the
//     parent, and the later one's prominence is the depth of the col between them, as in
//     topography. scipy gives both the full height, which would count every repetition of a
//     plateau's top value as a peak of the whole pulse height.
// Why the prominence threshold: the raw strict-maximum rule counts round-off. An exact plateau
// computed in floating point wobbles by a few ulps, and each wobble is a "peak": hundreds of
// them on the contact pressure's plateau. A threshold far below any physical oscillation
// (impactid's default is 1e-6 of the signal's scale) removes those and nothing else.
#pragma once

#include <span>

namespace impactid {

/// Number of peaks with prominence >= min_prominence. NaN samples make the result meaningless;
/// callers do not count peaks of unstable runs.
long count_peaks(std::span<const double> signal, double min_prominence);

/// Prominence of the peak whose flat top spans [first, last]; for tests and reports.
double peak_prominence(std::span<const double> signal, std::size_t first, std::size_t last);

}  // namespace impactid
