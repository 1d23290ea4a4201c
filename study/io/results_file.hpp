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
#include <vector>

#include "study/studies/study_results.hpp"

namespace impactid {

void write_results(const std::filesystem::path& path, const StudyResults& results);
/// The same with the per-point datasets compressed (Hdf5Writer::compress_large_datasets): for
/// shard files, which hold the whole grid but compute a part of it (study/studies/shard.hpp).
void write_results_compressed(const std::filesystem::path& path, const StudyResults& results);
/// Reads a file written by write_results. Throws Hdf5Error naming the file for a missing,
/// truncated, corrupt or foreign file.
StudyResults read_results(const std::filesystem::path& path);
/// One CSV per dataset shape: DIR/points.csv with one row per point in flat order (dimension
/// values, parameters, status, indicators; header cells name[units], just name when
/// dimensionless) and, for exactly two dimensions, DIR/<indicator>.csv as a matrix with the
/// first axis down and the second across (corner cell "<dim0>\<dim1>"). Numbers are the
/// shortest text that reads back as the same double (std::to_chars), NaN is written "nan". A
/// parameter or indicator column that is NaN at every point is left out (of points.csv, and its
/// matrix is not written); returns the names of those columns. Creates DIR; each file is written
/// as <file>.tmp and renamed. Throws std::runtime_error naming the file.
std::vector<std::string> export_csv(const StudyResults& results,
                                    const std::filesystem::path& directory);

}  // namespace impactid
