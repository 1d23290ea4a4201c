// The time stamp results files carry in their `date` attribute.
#pragma once

#include <ctime>
#include <string>

namespace impactid {

/// Now, UTC, ISO 8601 to the second: "2024-05-06T07:08:09Z".
inline std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

}  // namespace impactid
