// The one module that talks to HDF5 (C++ API, 1.10). Everything else writes and reads results
// through these functions, so HDF5's exceptions and handles stay here: failures come out as
// Hdf5Error with the file and object named.
//
// Files are written atomically: a writer builds the file in memory (HDF5's core driver) and
// commit() writes its image to "<path>.tmp", flushes it to disk (fsync) and renames it over
// <path>, so a reader never sees a half-written file and an interrupted or failed writer leaves
// the previous file intact and no temporary behind. HDF5 itself never writes to the disk: after
// a write failed for lack of space, HDF5 1.10 crashes in H5Fclose (issue 38), where the one
// write of the image fails cleanly, with the system's reason (No space left on device, Read-only
// file system) in the Hdf5Error.
//
// Every number is stored with a checksum that is verified on every read, so a flipped bit is an
// error naming the file and the object, never a value (issue 38):
//   - numeric datasets are chunked (whole when under 2^16 elements) with HDF5's Fletcher32
//     filter; HDF5 checks it on each read, in impactid and in any other reader (h5py, xarray,
//     netCDF-C), and deflate, where on, runs before it on write;
//   - HDF5's own metadata (object headers, chunk indexes) carries checksums in the 1.10 file
//     format, which the writer asks for (so reading needs HDF5 1.10 or later);
//   - text datasets store the strings' places in the global heap; up to 3000 strings they are
//     kept in the dataset's object header (compact storage), which HDF5's checksum covers
//     (HDF5 allows no Fletcher32 on variable-length data);
//   - what neither covers, the attributes (the plan's text lives in the file's global heap,
//     which has no checksum) and the text datasets' strings, is covered by one CRC-32 over all
//     of them, written at commit() as the root attribute kChecksumAttribute and checked when a
//     Hdf5Reader opens the file. HDF5 does not know it: other readers do not check it
//     (Python's open_results does, through this code). H5DS's dimension-scale bookkeeping is left
//     out: its object references are file addresses (h5repack changes them, not the study); CLASS,
//     NAME and REFERENCE_LIST sit in checksummed object headers, and DIMENSION_LIST, in the global
//     heap, is checked by its use: read_results requires one scale per axis, of matching length.
// A file without kChecksumAttribute (written before checksums, or by another program) is read
// unverified, with a note on stderr. A checksum that does not match is an Hdf5Error "FILE:
// OBJECT: data corrupted: …".
//
// Checksums are checked after HDF5 has parsed the structures holding them, and HDF5 1.10.8
// trusts some of those blindly: a damaged global-heap collection (where variable-length strings
// live, the plan's text among them) makes it copy ~10^18 bytes (SIGSEGV) or loop forever, and
// damaged groups and object headers make it free memory it never set, at once or in a later
// reader of the same bytes (scripts/fuzz's results fuzzer found each). So HDF5 never parses, in
// this process, bytes this process did not write. A Hdf5Reader first walks the file's global
// heap collections with the checks HDF5 lacks (a copy past a collection crashes or not
// depending on the memory around it: no trial read can rule it out), then reads the whole file
// in a child process (study/formats/first_read.hpp): every object, attribute, dataset and
// dimension scale, each answer or error recorded (study/formats/hdf5_answers.hpp) and handed
// back; the reader answers from them. A child that crashes or does not end within
// kFirstReadSeconds (+ 1 s per 10 MB) makes the Hdf5Error "FILE: damaged: reading it crashes
// HDF5 (…)". Bytes read once are answered again from memory; bytes this process wrote are read
// here, without a child.
//
// Files track the creation order of their root group's links and attributes (as netCDF-4
// does), so members() and attribute_names() list them in the order they were written.
//
// An object is not safe to share between threads; separate objects may be used from separate
// threads (Debian's HDF5 is built thread-safe and serialises its calls).
#pragma once

#include <H5Cpp.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "study/formats/hdf5_error.hpp"

namespace impactid {

class Hdf5Answers;

using Hdf5Dims = std::vector<hsize_t>;

/// The root attribute holding the CRC-32 of a file's attributes and text datasets (see above).
/// Hdf5Reader::attribute_names leaves it out: it describes the storage, not the content.
inline constexpr const char* kChecksumAttribute = "impactid_checksum";

/// What a Hdf5Reader does with a file without checksums: say so on stderr, or nothing (a probe
/// that only asks which kind of file it is; the reader that loads it says it).
enum class UncheckedFile { note, quiet };

class Hdf5Writer {
 public:
  /// Starts the file in memory (creating <path>'s parent folders). Throws Hdf5Error.
  explicit Hdf5Writer(std::filesystem::path path);
  ~Hdf5Writer();  // an uncommitted file is dropped: nothing of it is on disk
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  /// Attributes on an object ("/" is the root; groups and datasets by path).
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, long value);
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name,
                 std::span<const double> values);
  void attribute(const std::string& object, const std::string& name, std::span<const int> values);

  void group(const std::string& path);
  /// Numeric datasets of 4096 elements or more created after this call are also shuffled and
  /// deflated (zlib level 1): a shard's file, whose other shards' points are NaN,
  /// shrinks to about its own points. Readers need nothing: HDF5 undoes it.
  void compress_large_datasets(bool on) { compressed_ = on; }
  /// A row-major dataset of the given shape (product of dims == data.size()).
  void dataset(const std::string& path, std::span<const double> data, const Hdf5Dims& dims);
  void dataset(const std::string& path, std::span<const long> data, const Hdf5Dims& dims);
  void dataset(const std::string& path, std::span<const int> data, const Hdf5Dims& dims);
  void dataset(const std::string& path, const std::vector<std::string>& data);

  /// Marks a 1D dataset as a netCDF-4 style dimension scale named `dimension` (H5DS, the HDF5
  /// high-level library: attributes CLASS = "DIMENSION_SCALE" and NAME).
  void dimension_scale(const std::string& scale, const std::string& dimension);
  /// Attaches a dimension scale to dimension `index` of `dataset` (its DIMENSION_LIST).
  void attach_scale(const std::string& dataset, const std::string& scale, unsigned index);

  /// Writes the file to <path>.tmp, flushes it to disk and renames it over <path>; on failure
  /// the temporary file is removed and <path> is as it was. Throws Hdf5Error naming the file
  /// and the system's reason.
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, temporary_;
  std::optional<H5::H5File> file_;
  bool compressed_ = false;
};

/// Read access to a results file. Throws Hdf5Error naming the file for a missing, truncated or
/// corrupt file and for a missing object. Opening reads the whole file once (above), checking
/// the checksum of the attributes and text and each dataset's Fletcher32; the accessors then
/// answer from what was read, each throwing the error its reading met ("FILE: OBJECT: data
/// corrupted: …" for a checksum that does not match). Copies share what was read.
class Hdf5Reader {
 public:
  explicit Hdf5Reader(const std::filesystem::path& path,
                      UncheckedFile unchecked = UncheckedFile::note);

  /// False for a file written without checksums, read unverified.
  bool checksummed() const { return checksummed_; }

  bool exists(const std::string& path) const;
  /// Names of a group's members, in creation order when the file tracks it, else by name.
  std::vector<std::string> members(const std::string& group) const;
  Hdf5Dims shape(const std::string& dataset) const;
  std::vector<double> doubles(const std::string& dataset) const;
  std::vector<long> longs(const std::string& dataset) const;
  std::vector<int> ints(const std::string& dataset) const;
  std::vector<std::string> strings(const std::string& dataset) const;
  bool has_attribute(const std::string& object, const std::string& name) const;
  double attribute_double(const std::string& object, const std::string& name) const;
  long attribute_long(const std::string& object, const std::string& name) const;
  std::string attribute_string(const std::string& object, const std::string& name) const;
  std::vector<double> attribute_doubles(const std::string& object, const std::string& name) const;
  std::vector<int> attribute_ints(const std::string& object, const std::string& name) const;
  /// Names of an object's attributes, in creation order when the file tracks it, else by name.
  std::vector<std::string> attribute_names(const std::string& object) const;
  /// True for a string attribute, false for any other (numbers, references…).
  bool attribute_is_text(const std::string& object, const std::string& name) const;

  /// True if the dataset is a dimension scale (H5DS: CLASS = "DIMENSION_SCALE").
  bool is_dimension_scale(const std::string& dataset) const;
  /// Paths ("/alpha") of the dimension scales attached to dimension `index` of `dataset`, in
  /// attachment order; empty when none is attached.
  std::vector<std::string> attached_scales(const std::string& dataset, unsigned index) const;

 private:
  template <class T>
  T answer(std::string_view what, const std::string& object,
           const std::string& argument = {}) const;
  Hdf5Error unanswered(std::string_view what, const std::string& object,
                       const std::string& argument) const;

  std::filesystem::path path_;
  std::shared_ptr<const Hdf5Answers> answers_;
  bool checksummed_ = false;
};

}  // namespace impactid
