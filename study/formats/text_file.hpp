// Text files (CSV exports and histories) written as the HDF5 files are: to "<path>.tmp", then
// renamed over <path>, so that a reader never sees half a file and a failed write (a full disk,
// a file size limit, a read-only file system) leaves <path> as it was and no temporary behind.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <stdexcept>

namespace impactid {

struct TextFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Calls write(stream) on "<path>.tmp" and renames it over <path>. Throws TextFileError naming
/// the file and the system's reason ("No space left on device"); an exception from `write`
/// passes through, after the temporary file is removed.
void write_text_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

}  // namespace impactid
