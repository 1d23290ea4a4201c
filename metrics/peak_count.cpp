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

long count_peaks(std::span<const double> x, double min_prominence) {
  PeakCounter counter(min_prominence);
  for (const double v : x) counter.add(v);
  return counter.peaks();
}

}  // namespace impactid
