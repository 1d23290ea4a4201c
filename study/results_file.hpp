// The results of one study run as an HDF5 file — layout documented in results/README.md:
//   root attributes: impactid_version, git_revision, plan (full text), plan_name, study_kind,
//     method, threads, wall_time_s, date (UTC, ISO 8601), points_total, points_done, plus any
//     study attributes (the best point of an optimisation: best_<parameter>, best_objective…);
//   one 1D dataset per dimension, marked as a netCDF-4 dimension scale (h5py and xarray with
//     the h5netcdf engine open the file directly);
//   per point, shaped like the grid: one dataset per stored indicator (units, long_name,
//     definition attributes), `status` (int: −1 not done, 0 ok, 1 unstable, 2 failed), the
//     varied parameters and the derived beta and gamma; NaN where a point is not done or not ok.
// Files are replaced atomically (temporary file, then rename).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace impactid {

inline constexpr int kStatusNotDone = -1;  ///< then 0, 1, 2 = RunStatus ok, unstable, failed

struct ResultDimension {
  std::string name;  ///< also the dataset name
  std::string units;
  std::vector<double> values;
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
  std::vector<int> status;              ///< flat; size = product of dimension sizes
  std::vector<ResultColumn> parameters;  ///< varied parameters, beta, gamma
  std::vector<ResultColumn> indicators;
  std::vector<std::pair<std::string, double>> numeric_attributes;  ///< extra root attributes
  std::vector<std::pair<std::string, std::string>> text_attributes;

  long points_total() const { return static_cast<long>(status.size()); }
  long points_done() const;
  const ResultColumn* find_column(const std::string& name) const;  ///< parameter or indicator
};

/// Writes atomically. Throws Hdf5Error naming the file.
void write_results(const std::filesystem::path& path, const StudyResults& results);
/// Reads a file written by write_results. Throws Hdf5Error naming the file for a missing,
/// truncated, corrupt or foreign file.
StudyResults read_results(const std::filesystem::path& path);
/// One CSV per dataset shape: DIR/points.csv with one row per point (dimension values,
/// parameters, status, indicators) and, for 2D grids, DIR/<indicator>.csv as a matrix with the
/// first axis down and the second across. Throws std::runtime_error naming the file.
void export_csv(const StudyResults& results, const std::filesystem::path& directory);

}  // namespace impactid
