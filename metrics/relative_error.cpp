#include "metrics/relative_error.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace impactid {

double relative_error(std::span<const double> exact, std::span<const double> computed) {
  assert(exact.size() == computed.size());
  RelativeErrorSum sum;
  for (std::size_t i = 0; i < exact.size(); ++i) sum.add(exact[i], computed[i]);
  return sum.value();
}

}  // namespace impactid
