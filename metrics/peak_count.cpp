#include "metrics/peak_count.hpp"

#include <algorithm>

namespace impactid {

double peak_prominence(std::span<const double> x, std::size_t first, std::size_t last) {
  const double top = x[first];
  double left_base = top;
  // Ties are broken to the left: an earlier sample as high as the top ends the left search,
  // so of two equal summits the earlier is the parent and the later one's prominence is the
  // depth of the col between them (topographic prominence; scipy instead passes through equal
  // heights and gives every equal summit the full height).
  for (std::size_t j = first; j-- > 0;) {
    if (x[j] >= top) break;
    left_base = std::min(left_base, x[j]);
  }
  double right_base = top;
  for (std::size_t j = last + 1; j < x.size(); ++j) {
    if (x[j] > top) break;
    right_base = std::min(right_base, x[j]);
  }
  return top - std::max(left_base, right_base);
}

// The same rule in one pass with no memory, for sweeps: a hysteresis (zig-zag) filter. It waits
// for a rise of at least `min_prominence` above the lowest sample since the last counted peak,
// then follows the highest sample until a drop of at least `min_prominence` below it, counts one
// peak, and waits again. (Both steps also require a strict rise and drop, so a threshold <= 0
// counts every peak.) Why that is the same count: both equal the largest k for which the signal
// has samples t₀ < p₁ < t₁ < … < p_k < t_k with every p_j at least `min_prominence` above (and
// strictly above) its neighbours t_{j−1} and t_j.
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
long count_peaks(std::span<const double> x, double min_prominence) {
  long peaks = 0;
  if (x.empty()) return peaks;
  bool rising = false;  // a rise has been confirmed; the filter now waits for the drop
  double low = x[0];    // while waiting for the rise: the lowest sample since the last peak
  double high = 0.0;    // while waiting for the drop: the highest sample since the rise
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double v = x[i];
    if (!rising) {
      low = std::min(low, v);
      if (v > low && v - low >= min_prominence) {
        rising = true;
        high = v;
      }
    } else {
      high = std::max(high, v);
      if (v < high && high - v >= min_prominence) {
        ++peaks;
        rising = false;
        low = v;
      }
    }
  }
  return peaks;
}

}  // namespace impactid
