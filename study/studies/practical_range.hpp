// The practical range of a grid or list study: the points where every indicator stays within
// the plan's thresholds ([study.practical], e.g. eps_p <= 0.03 and nop_p <= 15), and how far
// they extend along each axis. This is the paper's "practical stage" made reproducible:
// δ ∈ [0.3, 1] for Newmark (sec. 4.1) and α ∈ [−0.5, −0.3] along δ = −1.5α for HHT (sec. 4.2)
// were read off Figs 3 and 4 by eye (Serfőző & Pere 2022, doi:10.1556/606.2022.00599); here
// they follow from stated thresholds.
//
// A point is practical when its status is ok and every thresholded indicator lies within its
// bounds (min <= value <= max). A point that is not ok is not practical (its indicators are
// NaN); a point that is not done is unknown (NaN in the mask) and counts neither way.
//
// Pure functions on a StudyResults table; thread-safe.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "study/plan/plan.hpp"
#include "study/studies/study_results.hpp"

namespace impactid {

/// The name of the results column holding the mask, and the prefix of its root attributes.
inline constexpr const char* kPracticalColumn = "practical";

/// The extent of the practical points along one dimension or parameter column.
struct PracticalExtent {
  std::string name;   ///< a dimension or a parameter column (a coupled delta, beta, …)
  std::string units;  ///< as in the results ("1" when dimensionless)
  bool is_dimension = false;
  double min = 0.0, max = 0.0;  ///< over the practical points, NaN values skipped; NaN if none
};

/// A maximal run of consecutive practical points of a one-dimensional study.
struct PracticalInterval {
  long first = 0, last = 0;     ///< indices along the dimension, first <= last
  double from = 0.0, to = 0.0;  ///< the smaller and the larger dimension value of the run
};

struct PracticalRange {
  std::string thresholds;  ///< thresholds_text() of the thresholds used
  /// Per point, flat like the results: 1 practical, 0 not, NaN not done.
  std::vector<double> mask;
  long points = 0;       ///< practical points
  long points_done = 0;  ///< points whose status is not "not done"
  long points_total = 0;
  /// The dimensions in order, then the parameter columns in order.
  std::vector<PracticalExtent> extents;
  /// One-dimensional studies only: the runs of consecutive practical points, in index order.
  /// A point that is not done ends a run like a point that is not practical.
  std::vector<PracticalInterval> intervals;
  bool one_dimensional = false;

  /// True for a one-dimensional study whose practical points form one interval.
  bool contiguous() const { return one_dimensional && intervals.size() == 1; }
};

/// "eps_p <= 0.03, nop_p <= 15" (a lower bound reads "x >= a", both "a <= x <= b").
std::string thresholds_text(std::span<const IndicatorConstraint> thresholds);

/// The practical range of `results` under `thresholds`. A threshold on an indicator the table
/// does not hold makes no point practical (plans cannot ask for one: load_plan() checks it).
PracticalRange practical_range(const StudyResults& results,
                               std::span<const IndicatorConstraint> thresholds);

/// "[0.3, 1]" or "[0.1, 0.2] [0.4, 1]" (values with 10 significant digits); "" when there is no
/// interval.
std::string intervals_text(const PracticalRange& range);

/// Adds the range to the table: the indicator column `practical` (units "1", definition = the
/// thresholds text) and the root attributes practical_thresholds (text), practical_points, and
/// practical_<name>_min / practical_<name>_max for every extent (numbers, NaN without a
/// practical point), plus practical_intervals (text) for a one-dimensional study. Whatever an
/// earlier call stored is replaced.
void store_practical_range(StudyResults& results, const PracticalRange& range);

/// Removes what store_practical_range() stored (nothing if there is none), so that a resumed
/// table holds only what the sweep computes.
void remove_practical_range(StudyResults& results);

/// One line for the terminal: "delta in [0.3, 1] (29 of 41 points; beta in [..], …)", or for
/// two and more dimensions "120 of 861 points: alpha in [..], delta in [..]; …". Parameters
/// that are NaN at every practical point are left out.
std::string practical_summary(const PracticalRange& range);

}  // namespace impactid
