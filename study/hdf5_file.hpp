// The one module that talks to HDF5 (C++ API, 1.10). Everything else writes and reads results
// through these functions, so HDF5's exceptions and handles stay here: failures come out as
// Hdf5Error with the file and object named.
//
// Files are written atomically: create() writes to "<path>.tmp" and commit() renames it over
// <path>, so a reader never sees a half-written file and an interrupted writer leaves the
// previous file intact.
#pragma once

#include <H5Cpp.h>

#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace impactid {

struct Hdf5Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using Hdf5Dims = std::vector<hsize_t>;

class Hdf5Writer {
 public:
  /// Starts <path>.tmp (creating parent folders). Throws Hdf5Error.
  explicit Hdf5Writer(std::filesystem::path path);
  ~Hdf5Writer();  // an uncommitted temporary file is removed
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  /// Attributes on an object ("/" is the root; groups and datasets by path).
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, long value);
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name,
                 std::span<const double> values);

  void group(const std::string& path);
  /// A row-major dataset of the given shape (product of dims == data.size()).
  void dataset(const std::string& path, std::span<const double> data, const Hdf5Dims& dims);
  void dataset(const std::string& path, std::span<const long> data, const Hdf5Dims& dims);
  void dataset(const std::string& path, const std::vector<std::string>& data);

  /// Marks a 1D dataset as a netCDF-4 style dimension scale named `dimension`, and attaches it
  /// to dimension `index` of each dataset in `users` (H5DS, the HDF5 high-level library).
  void dimension_scale(const std::string& scale, const std::string& dimension);
  void attach_scale(const std::string& dataset, const std::string& scale, unsigned index);

  /// Closes and renames the temporary file over the target. Throws Hdf5Error.
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  H5::H5Object& object(const std::string& path);
  std::filesystem::path path_, temporary_;
  std::optional<H5::H5File> file_;
  std::optional<H5::Group> group_handle_;
  std::optional<H5::DataSet> dataset_handle_;
};

/// Read access to a results file. Throws Hdf5Error naming the file for a missing, truncated or
/// corrupt file and for a missing object.
class Hdf5Reader {
 public:
  explicit Hdf5Reader(const std::filesystem::path& path);

  bool exists(const std::string& path) const;
  std::vector<std::string> members(const std::string& group) const;
  Hdf5Dims shape(const std::string& dataset) const;
  std::vector<double> doubles(const std::string& dataset) const;
  std::vector<long> longs(const std::string& dataset) const;
  std::vector<std::string> strings(const std::string& dataset) const;
  bool has_attribute(const std::string& object, const std::string& name) const;
  double attribute_double(const std::string& object, const std::string& name) const;
  long attribute_long(const std::string& object, const std::string& name) const;
  std::string attribute_string(const std::string& object, const std::string& name) const;
  std::vector<double> attribute_doubles(const std::string& object, const std::string& name) const;

 private:
  std::filesystem::path path_;
  mutable H5::H5File file_;  // HDF5 opens objects through non-const handles
};

}  // namespace impactid
