// The results of one study run as an HDF5 file — layout documented in results/README.md:
//   root attributes: format = "impactid-results-1" (read_results accepts nothing else),
//     impactid_version, git_revision, plan (full text), plan_name, study_kind, method, threads,
//     run_wall_time_s, date (UTC, ISO 8601), points_total, points_done, then the study attributes
//     (numeric_attributes, text_attributes: the best point of an optimisation…) in order;
//   one 1D float64 dataset per dimension (`units`), marked as a netCDF-4 dimension scale (h5py,
//     xarray with the h5netcdf engine and ncdump open the file directly);
//   per point, shaped like the grid, each with every dimension scale attached: `status` (int32:
//     −1 not done, 0 ok, 1 unstable, 2 failed; CF flag_values/flag_meanings), then the columns
//     (float64; units, long_name, definition if any, role = "parameter" or "indicator"): the
//     varied parameters and the derived beta and gamma, then the indicators. NaN where a point
//     is not done, and in every indicator but wall_time_s where a point is not ok.
// Files are replaced atomically (temporary file, fsync, rename); a failed write leaves the
// previous file as it was. Two concurrent writers of one path would share its temporary file:
// a study writes its file from one thread (the sweep's checkpoints come from the calling thread).
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
  ResultColumn* find_column(const std::string& name) {
    return const_cast<ResultColumn*>(std::as_const(*this).find_column(name));
  }
};

/// Writes atomically. Throws Hdf5Error naming the file, also for a table that cannot be stored
/// as it is (no dimension, a size that does not match the grid, a status code outside −1…2, a
/// name used twice or containing '/', a study attribute with a reserved name).
void write_results(const std::filesystem::path& path, const StudyResults& results);
/// The same with the per-point datasets compressed (Hdf5Writer::compress_large_datasets): for
/// shard files, which hold the whole grid but compute a part of it (study/shard.hpp).
void write_results_compressed(const std::filesystem::path& path, const StudyResults& results);
/// Reads a file written by write_results. Throws Hdf5Error naming the file for a missing,
/// truncated, corrupt or foreign file.
StudyResults read_results(const std::filesystem::path& path);
/// One CSV per dataset shape: DIR/points.csv with one row per point in flat order (dimension
/// values, parameters, status, indicators; header cells name[units], just name when
/// dimensionless) and, for exactly two dimensions, DIR/<indicator>.csv as a matrix with the
/// first axis down and the second across (corner cell "<dim0>\<dim1>"). Numbers have 17
/// significant digits (they read back exactly), NaN is written "nan". Creates DIR; each file is
/// written as <file>.tmp and renamed. Throws std::runtime_error naming the file.
void export_csv(const StudyResults& results, const std::filesystem::path& directory);

}  // namespace impactid
