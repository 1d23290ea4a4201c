// The first read of an HDF5 file in this process, in a child process
// (study/formats/child_process.hpp), and what it taught: Hdf5Reader asks before it opens a file
// (study/formats/hdf5_file.hpp says why).
//
// Outcomes are kept by the SHA-256 of the file's bytes, so a file read again (a results file
// opened by several readers in one command, a file this process wrote and reads back) costs no
// second child, and a damaged one is refused at once instead of after the bound again. Bytes
// are what HDF5 parses, so the same bytes take the same paths; a file whose bytes changed is a
// new file.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>

#include "study/formats/child_process.hpp"

namespace impactid {

/// The bound on the first read of a file under 10 MB (1 s more per 10 MB): reading a results
/// file takes milliseconds, under the sanitizers tens of them; a damaged one can loop forever.
inline constexpr double kFirstReadSeconds = 5;

/// What check_first_read learnt of a file that did not fail, for the caller to keep once it has
/// read the file itself (keep()): keeping it takes memory, and between the child's start and
/// the caller's own read this process must not touch its heap (first_read.cpp says why).
class FirstRead {
 public:
  void keep() const;

 private:
  friend FirstRead check_first_read(const std::filesystem::path& path,
                                    const std::function<void()>& read_everything);
  std::array<char, 32> digest_{};  // SHA-256
  bool to_keep_ = false;
  ChildOutcome outcome_;
};

/// Checks the file's global heap collections (first_read.cpp says why), then runs
/// `read_everything` (a walk of the whole file at `path`, the same calls the caller makes next)
/// in a child process unless these bytes were read before. Throws Hdf5Error "PATH: damaged: …"
/// for an inconsistent collection, or when the child crashed or did not end within the bound;
/// returns otherwise (fork failed: nothing learnt, the caller reads as before), and the caller
/// then reads the file at once, before anything else takes or gives back memory.
[[nodiscard]] FirstRead check_first_read(const std::filesystem::path& path,
                                         const std::function<void()>& read_everything);

/// Files HDF5 wrote in this process (Hdf5Writer::commit's image): readable by construction.
/// Only images up to kRememberedImageBytes: the digest costs about 2 ms per MB at every commit,
/// and a large sweep's checkpoints (160 MB at 10⁶ points) are read back by a later process,
/// which reads them in a child anyway.
inline constexpr std::size_t kRememberedImageBytes = std::size_t{16} << 20;
void remember_readable(std::span<const char> image);

}  // namespace impactid
