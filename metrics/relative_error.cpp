#include "metrics/relative_error.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace impactid {

double RelativeErrorSum::value() const {
  return reference_ > 0.0 ? difference_ / reference_ : std::numeric_limits<double>::quiet_NaN();
}

double relative_error(std::span<const double> exact, std::span<const double> computed) {
  assert(exact.size() == computed.size());
  RelativeErrorSum sum;
  for (std::size_t i = 0; i < exact.size(); ++i) sum.add(exact[i], computed[i]);
  return sum.value();
}

}  // namespace impactid
