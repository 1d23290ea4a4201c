// The one shape of a rejected input value, shared by every validator so that the command line
// and plan files can each phrase it in their own names (`--elements`, `scene.elements`).
#pragma once

#include <optional>
#include <string>

namespace impactid {

struct ParameterError {
  std::string field;       ///< snake_case key, e.g. "elements", "alpha"
  std::string value;       ///< the offending value as the user would write it
  std::string constraint;  ///< what it must satisfy, e.g. "must be a positive integer"
};

/// Shortest round-trip text of a double ("0.1", "nan", "-inf").
std::string format_value(double value);

/// Returns an error unless lo <= value <= hi (NaN always fails).
std::optional<ParameterError> require_in_range(const char* field, double value, double lo,
                                               double hi, const char* constraint);
/// require_in_range from the smallest normal double to the largest: "must be positive and finite".
std::optional<ParameterError> require_positive_finite(const char* field, double value);

}  // namespace impactid
