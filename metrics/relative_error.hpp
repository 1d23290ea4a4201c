// The relative error of eq. 18 (Serfőző & Pere 2022):
//   ε = Σ_i |p_i^exact − p_i^FEM| / Σ_i |p_i^exact|
// over the samples of a run. Undefined (NaN) when the exact values are all zero.
#pragma once

#include <span>

namespace impactid {

class RelativeErrorSum {
 public:
  void add(double exact, double computed);
  /// NaN when no exact value was non-zero.
  double value() const;

 private:
  double difference_ = 0.0;
  double reference_ = 0.0;
};

double relative_error(std::span<const double> exact, std::span<const double> computed);

}  // namespace impactid
