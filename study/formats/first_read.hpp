// The reading of an HDF5 file's bytes in a child process (study/formats/child_process.hpp):
// Hdf5Reader's walk of the whole file runs there and hands its answers over
// (study/formats/hdf5_answers.hpp), so that HDF5 never parses bytes this process did not write
// (study/formats/hdf5_file.hpp says why).
//
// What was learnt is kept by the SHA-256 of the file's bytes, so a file read again (a results
// file opened by several readers in one command) costs no second child, and a damaged one is
// refused at once instead of after the bound again. Bytes are what HDF5 parses, so the same
// bytes give the same answers; a file whose bytes changed is a new file.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>

#include "study/formats/hdf5_answers.hpp"

namespace impactid {

/// The bound on a child's reading of a file under 10 MB (1 s more per 10 MB): reading a results
/// file takes milliseconds, under the sanitizers tens of them; a damaged one can loop forever.
inline constexpr double kFirstReadSeconds = 5;

/// The answers of the file at `path`: what `walk` (a walk of the whole file that records every
/// answer a reader may ask for, going on past errors) records. Bytes this process wrote are
/// walked in this process; other bytes in a child process unless they were answered before.
/// Throws Hdf5Error "PATH: damaged: …" when the file's global heap collections are
/// inconsistent (first_read.cpp says why they are checked first), or when the child crashed or
/// did not end within the bound. When no child can be started (fork failed: no memory, no
/// process slot) the walk runs in this process, the one way left to read the file.
std::shared_ptr<const Hdf5Answers> first_read(const std::filesystem::path& path,
                                               const std::function<Hdf5Answers()>& walk);

/// Files HDF5 wrote in this process (Hdf5Writer::commit's image): readable by construction, so
/// walked in this process. Only images up to kRememberedImageBytes: the digest costs about 2 ms
/// per MB at every commit, and a large sweep's checkpoints (160 MB at 10⁶ points) are read back
/// by a later process, which reads them in a child anyway.
inline constexpr std::size_t kRememberedImageBytes = std::size_t{16} << 20;
void remember_readable(std::span<const char> image);

}  // namespace impactid
