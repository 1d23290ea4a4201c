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

#include <algorithm>
#include <limits>
#include <span>

namespace impactid {

// The same rule in one pass with no memory, sample by sample, for sweeps: a hysteresis (zig-zag)
// filter. It waits for a rise of at least `min_prominence` above the lowest sample since the last
// counted peak, then follows the highest sample until a drop of at least `min_prominence` below
// it, counts one peak, and waits again. (Both steps also require a strict rise and drop, so a
// threshold <= 0 counts every peak.) Why that is the same count: both equal the largest k for
// which the signal has samples t₀ < p₁ < t₁ < … < p_k < t_k with every p_j at least
// `min_prominence` above (and strictly above) its neighbours t_{j−1} and t_j.
//   - Prominent peaks give such a sequence: between two of them lies a base of the lower one
//     (of equal ones, the later), which is at least `min_prominence` below both; the outer
//     bases close it.
//   - Such a sequence gives as many prominent peaks: the earliest highest sample of each
//     [t_{j−1}, t_j] tops a peak whose nearest higher samples lie beyond t_{j−1} and t_j, so its
//     bases are no higher than x[t_{j−1}] and x[t_j].
//   - The filter builds a longest sequence: it ends each rise and each drop at the first sample
//     that completes it, and keeps the lowest (highest) candidate, so no sequence is ahead of it.
// Rounding cannot split them: fl(a − b) is monotone in a and in b, so "top − base >= threshold"
// and the filter's comparisons agree on every pair of samples. tests/peak_count_test.cpp checks
// it against peak_prominence() on random signals with ties, plateaus and slow ramps.
//
// Inline and fed one sample at a time, so that the indicators count the peaks of the pressure and
// of the velocity in the same loop as the error sums (metrics/indicators.cpp): one pass over a
// run's samples instead of three.
class PeakCounter {
 public:
  explicit PeakCounter(double min_prominence) : threshold_(min_prominence) {}

  /// The next sample (finite).
  void add(double v) {
    if (!rising_) {
      low_ = std::min(low_, v);  // the first sample: +inf, so low_ becomes it and nothing rises
      if (v > low_ && v - low_ >= threshold_) {
        rising_ = true;
        high_ = v;
      }
    } else {
      high_ = std::max(high_, v);
      if (v < high_ && high_ - v >= threshold_) {
        ++peaks_;
        rising_ = false;
        low_ = v;
      }
    }
  }
  /// Peaks counted so far (a peak counts once the drop after it is complete).
  long peaks() const { return peaks_; }

 private:
  double threshold_;
  bool rising_ = false;  // a rise has been confirmed; the filter now waits for the drop
  // While waiting for the rise: the lowest sample since the last peak (+inf before the first).
  double low_ = std::numeric_limits<double>::infinity();
  double high_ = 0.0;  // while waiting for the drop: the highest sample since the rise
  long peaks_ = 0;
};

/// Number of peaks with prominence >= min_prominence. NaN samples make the result meaningless;
/// callers do not count peaks of unstable runs.
long count_peaks(std::span<const double> signal, double min_prominence);

/// Prominence of the peak whose flat top spans [first, last]; for tests and reports.
double peak_prominence(std::span<const double> signal, std::size_t first, std::size_t last);

}  // namespace impactid
