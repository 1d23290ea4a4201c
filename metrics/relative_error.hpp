// The relative error of eq. 18 (Serfőző & Pere 2022):
//   ε = Σ_i |p_i^exact − p_i^FEM| / Σ_i |p_i^exact|
// over the samples of a run. Undefined (NaN) when the exact values are all zero.
#pragma once

#include <cmath>
#include <limits>
#include <span>

namespace impactid {

class RelativeErrorSum {
 public:
  // Inline: the indicators add two samples per time step of every sweep point.
  void add(double exact, double computed) {
    difference_ += std::abs(exact - computed);
    reference_ += std::abs(exact);
  }
  /// NaN when no exact value was non-zero. Inline, as add(): a call that takes the sum's address
  /// made GCC keep both sums in memory in the callers' sample loops (a store and a load on each
  /// add's dependency chain; docs/performance.md).
  double value() const {
    return reference_ > 0.0 ? difference_ / reference_ : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double difference_ = 0.0;
  double reference_ = 0.0;
};

double relative_error(std::span<const double> exact, std::span<const double> computed);

}  // namespace impactid
