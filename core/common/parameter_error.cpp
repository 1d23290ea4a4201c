#include "core/common/parameter_error.hpp"

#include <limits>

#include <charconv>
#include <cmath>

namespace impactid {

std::string format_value(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::optional<ParameterError> require_in_range(const char* field, double value, double lo,
                                               double hi, const char* constraint) {
  if (!(value >= lo && value <= hi)) return ParameterError{field, format_value(value), constraint};
  return std::nullopt;
}

std::optional<ParameterError> require_positive_finite(const char* field, double value) {
  return require_in_range(field, value, std::numeric_limits<double>::min(),
                          std::numeric_limits<double>::max(), "must be positive and finite");
}

}  // namespace impactid
