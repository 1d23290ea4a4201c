#include "metrics/peak_count.hpp"

#include <algorithm>
#include <limits>
#include <vector>

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

// The same rule in O(n), for sweeps: scanning from each peak to its bases costs O(n) per peak,
// and a ringing signal has hundreds of peaks (50 µs of a 150 µs run). Two monotonic-stack
// passes give every sample i its nearest higher-or-equal sample to the left, with the lowest
// sample in between, and its nearest strictly higher sample to the right, with the lowest in
// between; a peak's bases are those minima at its first and last samples. The entries popped
// when i is pushed are exactly the samples between i and that neighbour, and their own
// intervals tile that range, so each minimum is folded from the popped entries' minima.
// tests/peak_count_test.cpp checks it against peak_prominence() on random signals.
long count_peaks(std::span<const double> x, double min_prominence) {
  const std::size_t n = x.size();
  if (n < 3) return 0;
  struct Entry {
    std::size_t index;
    double low;  // lowest sample in (neighbour, index]: the interval this entry covers
  };
  std::vector<Entry> stack;
  stack.reserve(n);
  // left_low[i]: the lowest sample strictly between i and its left neighbour (+inf if none).
  std::vector<double> left_low(n), right_low(n);
  constexpr double kNone = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    double low = kNone;
    while (!stack.empty() && x[stack.back().index] < x[i]) {
      low = std::min(low, stack.back().low);
      stack.pop_back();
    }
    left_low[i] = low;
    stack.push_back({i, std::min(low, x[i])});
  }
  stack.clear();
  for (std::size_t i = n; i-- > 0;) {
    double low = kNone;
    while (!stack.empty() && x[stack.back().index] <= x[i]) {
      low = std::min(low, stack.back().low);
      stack.pop_back();
    }
    right_low[i] = low;
    stack.push_back({i, std::min(low, x[i])});
  }

  long peaks = 0;
  std::size_t i = 1;
  while (i + 1 < n) {
    if (!(x[i - 1] < x[i])) {
      ++i;
      continue;
    }
    std::size_t last = i;  // extend over a flat top
    while (last + 1 < n && x[last + 1] == x[i]) ++last;
    if (last + 1 < n && x[last + 1] < x[i]) {
      const double top = x[i];
      const double left_base = std::min(top, left_low[i]);
      const double right_base = std::min(top, right_low[last]);
      if (top - std::max(left_base, right_base) >= min_prominence) ++peaks;
    }
    i = last + 1;
  }
  return peaks;
}

}  // namespace impactid
