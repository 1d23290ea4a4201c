// The results of one study in memory: its dimensions (the grid's axes, or one axis of list points
// or evaluations), every point's status, and per point the varied parameters and the indicators.
// Sweeps, optimisations and work-precision studies fill it; study/io/results_file.hpp writes it
// as an HDF5 file (and CSV) and reads it back for --resume.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace impactid {

inline constexpr int kStatusNotDone = -1;  ///< then 0, 1, 2 = RunStatus ok, unstable, failed

/// The name of the verdict column (metrics/verdict.hpp): an indicator column whose values are the
/// Verdict codes 0 accurate … 5 failed (their order in all_verdicts()), NaN for a point not done;
/// the root attribute `verdict_thresholds` records the thresholds (the plan's [output]).
/// Grid, list and work-precision studies have it (study/studies/sweep.hpp: add_verdict_column).
inline constexpr const char* kVerdictColumn = "verdict";

struct ResultDimension {
  std::string name;  ///< also the dataset name
  std::string units;
  std::vector<double> values;
  /// A choice axis (contact = ["lagrange", "penalty"]): the word of each value, whose values are
  /// then 0, 1, …; empty for a numeric dimension. Stored as CF flag_values and flag_meanings.
  std::vector<std::string> labels;
};

struct ResultColumn {
  std::string name;  ///< dataset name
  std::string units;
  std::string long_name;
  std::string definition;      ///< may be empty
  std::vector<double> values;  ///< flat, row-major over the dimensions
};

struct StudyResults {
  std::string plan_name, plan_text, study_kind, method;
  std::string impactid_version, git_revision, date;
  long threads = 1;
  double wall_time_s = 0.0;
  std::vector<ResultDimension> dimensions;
  std::vector<int> status;               ///< flat; size = product of dimension sizes
  std::vector<ResultColumn> parameters;  ///< varied parameters, beta, gamma
  std::vector<ResultColumn> indicators;
  std::vector<std::pair<std::string, double>> numeric_attributes;  ///< extra root attributes
  std::vector<std::pair<std::string, std::string>> text_attributes;

  long points_total() const { return static_cast<long>(status.size()); }
  long points_done() const;
  const ResultColumn* find_column(const std::string& name) const;  ///< parameter or indicator
  ResultColumn* find_column(const std::string& name) {
    return const_cast<ResultColumn*>(std::as_const(*this).find_column(name));
  }
};

/// Writes atomically. Throws Hdf5Error naming the file, also for a table that cannot be stored
/// as it is (no dimension, a size that does not match the grid, a status code outside −1…2, a
/// name used twice or containing '/', a study attribute with a reserved name).
}  // namespace impactid
