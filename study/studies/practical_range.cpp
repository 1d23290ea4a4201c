#include "study/studies/practical_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/parameter_error.hpp"

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kAttributePrefix = "practical_";

bool within(const IndicatorConstraint& t, double value) {
  if (std::isnan(value)) return false;
  if (t.min && !(value >= *t.min)) return false;
  if (t.max && !(value <= *t.max)) return false;
  return true;
}

// Ten significant digits: the texts are for reading (0.4225, not 0.42250000000000004, for a
// beta computed from delta = 0.3); the exact values are the numeric attributes.
std::string readable(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string interval_text(double from, double to) {
  std::string out = "[";  // appended rather than "[" + …: GCC 12 warns falsely (-Wrestrict)
  out += readable(from);
  out += ", ";
  out += readable(to);
  out += "]";
  return out;
}

// "alpha in [-0.5, -0.3]", or "alpha: none" without a practical point.
std::string extent_text(const PracticalExtent& e) {
  if (std::isnan(e.min)) return e.name + ": none";
  return e.name + " in " + interval_text(e.min, e.max);
}

}  // namespace

std::string thresholds_text(std::span<const IndicatorConstraint> thresholds) {
  std::string out;
  for (const IndicatorConstraint& t : thresholds) {
    if (!out.empty()) out += ", ";
    if (t.min && t.max) {
      out += format_value(*t.min) + " <= " + t.indicator + " <= " + format_value(*t.max);
    } else if (t.max) {
      out += t.indicator + " <= " + format_value(*t.max);
    } else if (t.min) {
      out += t.indicator + " >= " + format_value(*t.min);
    }
  }
  return out;
}

PracticalRange practical_range(const StudyResults& results,
                               std::span<const IndicatorConstraint> thresholds) {
  PracticalRange range;
  range.thresholds = thresholds_text(thresholds);
  range.points_total = results.points_total();
  range.one_dimensional = results.dimensions.size() == 1;
  const auto total = static_cast<std::size_t>(range.points_total);

  std::vector<const ResultColumn*> columns;
  for (const IndicatorConstraint& t : thresholds)
    columns.push_back(results.find_column(t.indicator));

  range.mask.assign(total, kNaN);
  for (std::size_t i = 0; i < total; ++i) {
    const int status = results.status[i];
    if (status == kStatusNotDone) continue;
    ++range.points_done;
    bool practical = status == 0;  // RunStatus::ok
    for (std::size_t k = 0; practical && k < thresholds.size(); ++k) {
      practical = columns[k] && within(thresholds[k], columns[k]->values[i]);
    }
    range.mask[i] = practical ? 1.0 : 0.0;
    if (practical) ++range.points;
  }

  // Extents: dimension values through each point's grid index (row-major, last fastest).
  for (const ResultDimension& d : results.dimensions) {
    range.extents.push_back({d.name, d.units, true, kNaN, kNaN});
  }
  for (const ResultColumn& c : results.parameters) {
    range.extents.push_back({c.name, c.units, false, kNaN, kNaN});
  }
  const auto include = [](PracticalExtent& e, double v) {
    if (std::isnan(v)) return;
    e.min = std::isnan(e.min) ? v : std::min(e.min, v);
    e.max = std::isnan(e.max) ? v : std::max(e.max, v);
  };
  std::vector<std::size_t> index(results.dimensions.size(), 0);
  for (std::size_t i = 0; i < total; ++i) {
    if (range.mask[i] == 1.0) {
      for (std::size_t d = 0; d < index.size(); ++d) {
        include(range.extents[d], results.dimensions[d].values[index[d]]);
      }
      for (std::size_t c = 0; c < results.parameters.size(); ++c) {
        include(range.extents[index.size() + c], results.parameters[c].values[i]);
      }
    }
    for (std::size_t d = index.size(); d-- > 0;) {
      if (++index[d] < results.dimensions[d].values.size()) break;
      index[d] = 0;
    }
  }

  if (range.one_dimensional) {
    const std::vector<double>& values = results.dimensions[0].values;
    for (std::size_t i = 0; i < total; ++i) {
      if (range.mask[i] != 1.0) continue;
      const bool extends =
          !range.intervals.empty() && range.intervals.back().last == static_cast<long>(i) - 1;
      if (extends) {
        range.intervals.back().last = static_cast<long>(i);
      } else {
        range.intervals.push_back({static_cast<long>(i), static_cast<long>(i), 0.0, 0.0});
      }
    }
    for (PracticalInterval& run : range.intervals) {
      const double a = values[static_cast<std::size_t>(run.first)];
      const double b = values[static_cast<std::size_t>(run.last)];
      run.from = std::min(a, b);
      run.to = std::max(a, b);
    }
  }
  return range;
}

std::string intervals_text(const PracticalRange& range) {
  std::string out;
  for (const PracticalInterval& run : range.intervals) {
    if (!out.empty()) out += " ";
    out += interval_text(run.from, run.to);
  }
  return out;
}

void remove_practical_range(StudyResults& results) {
  std::erase_if(results.indicators,
                [](const ResultColumn& c) { return c.name == kPracticalColumn; });
  const auto prefixed = [](const auto& attribute) {
    return attribute.first.rfind(kAttributePrefix, 0) == 0;
  };
  std::erase_if(results.numeric_attributes, prefixed);
  std::erase_if(results.text_attributes, prefixed);
}

void store_practical_range(StudyResults& results, const PracticalRange& range) {
  remove_practical_range(results);
  results.indicators.push_back({kPracticalColumn, "1",
                                "practical point: 1 where the status is ok and " +
                                    range.thresholds +
                                    ", 0 where not, NaN where the point is not done",
                                range.thresholds, range.mask});
  const std::string prefix = kAttributePrefix;
  results.text_attributes.emplace_back(prefix + "thresholds", range.thresholds);
  if (range.one_dimensional) {
    results.text_attributes.emplace_back(prefix + "intervals", intervals_text(range));
  }
  results.numeric_attributes.emplace_back(prefix + "points", static_cast<double>(range.points));
  for (const PracticalExtent& e : range.extents) {
    results.numeric_attributes.emplace_back(prefix + e.name + "_min", e.min);
    results.numeric_attributes.emplace_back(prefix + e.name + "_max", e.max);
  }
}

std::string practical_summary(const PracticalRange& range) {
  const std::string count =
      std::to_string(range.points) + " of " + std::to_string(range.points_total) + " points" +
      (range.points_done < range.points_total
           ? " (" + std::to_string(range.points_total - range.points_done) + " not done)"
           : "");
  if (range.points == 0) return "no practical point (" + count + ")";
  std::string dimensions, others;
  for (const PracticalExtent& e : range.extents) {
    // A parameter no practical point has (delta of a list's cdm point) says nothing here.
    if (!e.is_dimension && std::isnan(e.min)) continue;
    std::string& out = e.is_dimension ? dimensions : others;
    if (!out.empty()) out += ", ";
    out += extent_text(e);
  }
  if (range.one_dimensional) {
    const std::string name = range.extents.front().name;
    return name + " in " + intervals_text(range) + " (" + count +
           (others.empty() ? "" : "; " + others) + ")";
  }
  return count + ": " + dimensions + (others.empty() ? "" : "; " + others);
}

}  // namespace impactid
