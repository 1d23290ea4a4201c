#include "study/formats/first_read.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "study/formats/child_process.hpp"
#include "study/formats/hdf5_error.hpp"

namespace impactid {
namespace {

using Digest = std::string;  // SHA-256, 32 raw bytes

class Sha256 {
 public:
  Sha256() : context_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    if (!context_ || EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) != 1) {
      throw Hdf5Error("SHA-256: OpenSSL cannot start a digest");
    }
  }
  void add(const void* bytes, std::size_t size) { EVP_DigestUpdate(context_.get(), bytes, size); }
  Digest digest() {
    std::array<unsigned char, EVP_MAX_MD_SIZE> out{};
    unsigned length = 0;
    EVP_DigestFinal_ex(context_.get(), out.data(), &length);
    return Digest(reinterpret_cast<const char*>(out.data()), length);
  }

 private:
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> context_;
};

// A file's bytes, mapped read-only; empty when it cannot be read or is empty (the child, and
// then the reader, say why).
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& path) {
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    struct stat st {};
    if (fstat(fd, &st) == 0 && st.st_size > 0) {
      void* at = mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (at != MAP_FAILED) {
        data_ = static_cast<const unsigned char*>(at);
        size_ = static_cast<std::size_t>(st.st_size);
      }
    }
    close(fd);
  }
  ~MappedFile() {
    if (data_) munmap(const_cast<unsigned char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::span<const unsigned char> bytes() const { return {data_, size_}; }

 private:
  const unsigned char* data_ = nullptr;
  std::size_t size_ = 0;
};

std::uint64_t little_endian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int k = bytes - 1; k >= 0; --k) v = (v << 8) | p[k];
  return v;
}

// HDF5 1.10.8 decodes a global heap collection (where variable-length strings live: every text
// attribute and text dataset) without checking its objects' lengths against the collection
// (H5HG__cache_heap_deserialize), then copies an object of the length it decoded (H5HG_read:
// past the collection, a crash or not, depending on what lies there) or loops for ever on a
// free-space object of length 0. Whether it crashes depends on the memory around the copy, so
// a child that survived it says nothing of this process: the collections are walked here, as
// HDF5 walks them, with the checks it lacks. A collection is found by its header, "GCOL",
// version 1, three zero bytes (8 bytes no number or text of a results file holds), then its
// size; lengths are 8 bytes (HDF5's default, which impactid's files use). Returns what is
// wrong with the first inconsistent collection, or nothing.
std::optional<std::string> inconsistent_global_heap(std::span<const unsigned char> file) {
  static constexpr unsigned char kHeader[] = {'G', 'C', 'O', 'L', 1, 0, 0, 0};
  constexpr std::size_t kCollectionHeader = 16, kObjectHeader = 16;
  const auto* const begin = file.data();
  const auto* const end = begin + file.size();
  for (const unsigned char* c = begin;
       (c = std::search(c, end, std::begin(kHeader), std::end(kHeader))) != end; ++c) {
    const std::size_t offset = static_cast<std::size_t>(c - begin);
    const auto where = [&](const std::string& what) {
      return "its global heap collection at byte " + std::to_string(offset) + " " + what;
    };
    if (file.size() - offset < kCollectionHeader) return where("is cut short");
    const std::uint64_t size = little_endian(c + 8, 8);
    if (size < kCollectionHeader || size > file.size() - offset) {
      return where("claims " + std::to_string(size) + " bytes, past the file's end");
    }
    const unsigned char* const stop = c + size;
    for (const unsigned char* p = c + kCollectionHeader; p < stop;) {
      const auto left = static_cast<std::uint64_t>(stop - p);
      if (left < kObjectHeader) break;  // too small for an object: free space, as HDF5 takes it
      const auto index = little_endian(p, 2);
      const std::uint64_t length = little_endian(p + 8, 8);
      // An object takes its header and its data padded to 8 bytes; the free-space object
      // (index 0) gives its whole extent, header included.
      const std::uint64_t need =
          index > 0 ? (length > left ? left + 1 : kObjectHeader + (length + 7) / 8 * 8) : length;
      if (need == 0 || need > left) {
        return where("holds an object (index " + std::to_string(index) + ") of " +
                     std::to_string(length) + " bytes, past its end");
      }
      p += need;
    }
  }
  return std::nullopt;
}

// What this process learnt, by digest. Bounded: past kMaxKept entries it starts again (a
// forgotten file costs one more child, nothing else).
class FirstReads {
 public:
  std::optional<ChildOutcome> find(const Digest& digest) {
    std::lock_guard lock(mutex_);
    const auto at = outcomes_.find(digest);
    if (at == outcomes_.end()) return std::nullopt;
    return at->second;
  }
  void keep(const Digest& digest, const ChildOutcome& outcome) {
    std::lock_guard lock(mutex_);
    if (outcomes_.size() >= kMaxKept) outcomes_.clear();
    outcomes_[digest] = outcome;
  }

 private:
  static constexpr std::size_t kMaxKept = 4096;
  std::mutex mutex_;
  std::unordered_map<Digest, ChildOutcome> outcomes_;
};

FirstReads& first_reads() {
  static FirstReads reads;
  return reads;
}

constexpr const char* kWhatToDo = " (the file is damaged; use a backup or run it again)";

}  // namespace

// Why the parent touches no heap from the child's start to its own read: HDF5 1.10 reads memory
// it never set on some damaged files (it frees a damaged group's link table entries it never
// filled; it frees object-header blocks from its free lists), and what that memory holds is
// whatever the heap held. The child starts from this process's heap as it is at the fork; if
// the parent then takes or gives back memory before its own read (a digest kept in the cache,
// a message string freed), its HDF5 calls get other blocks than the child's, and a file the
// child read without harm crashed the parent (results_fuzzer findings). With the heap left
// as it was, the parent's read takes the child's path through the same memory. So the digest
// is kept in an array, the messages are made only when the file is refused, and the outcome is
// kept by the caller (FirstRead::keep) after its read.
FirstRead check_first_read(const std::filesystem::path& path,
                           const std::function<void()>& read_everything) {
  FirstRead first;
  bool has_digest = false;
  double seconds = kFirstReadSeconds;
  std::optional<ChildOutcome> outcome;
  {
    const MappedFile mapped(path);
    const std::span<const unsigned char> bytes = mapped.bytes();
    seconds += static_cast<double>(bytes.size()) / 1e7;
    if (const std::optional<std::string> wrong = inconsistent_global_heap(bytes)) {
      throw Hdf5Error(path.string() + ": damaged: " + *wrong +
                      " (HDF5 1.10 would read past it); nothing of it was read" + kWhatToDo);
    }
    if (!bytes.empty()) {
      Sha256 sha;
      sha.add(bytes.data(), bytes.size());
      const Digest digest = sha.digest();
      std::copy_n(digest.begin(), std::min(digest.size(), first.digest_.size()),
                  first.digest_.begin());
      has_digest = true;
      outcome = first_reads().find(digest);
    }
  }  // everything of the check given back before the child starts
  if (!outcome) {
    outcome = run_in_child(read_everything, seconds);
    first.to_keep_ = has_digest && outcome->kind != ChildOutcome::Kind::not_run;
    first.outcome_ = *outcome;
  }
  const auto refuse = [&](const std::string& why) {
    first.keep();  // this process reads no more of it: memory is free to use
    return Hdf5Error(path.string() + ": damaged: " + why +
                     "; it was read first in a separate process, so nothing else is lost" +
                     kWhatToDo);
  };
  switch (outcome->kind) {
    case ChildOutcome::Kind::crashed:
      throw refuse("reading it crashes HDF5 (" +
                   (outcome->signal ? std::string(strsignal(outcome->signal))
                                    : "exit status " + std::to_string(outcome->exit_status)) +
                   ")");
    case ChildOutcome::Kind::timed_out:
      throw refuse("reading it did not end within " + std::to_string(std::lround(seconds)) + " s");
    case ChildOutcome::Kind::ended:
    case ChildOutcome::Kind::not_run:
      break;
  }
  return first;
}

void FirstRead::keep() const {
  if (to_keep_) first_reads().keep(Digest(digest_.data(), digest_.size()), outcome_);
}

void remember_readable(std::span<const char> image) {
  if (image.size() > kRememberedImageBytes) return;
  Sha256 sha;
  sha.add(image.data(), image.size());
  ChildOutcome ended;
  ended.kind = ChildOutcome::Kind::ended;
  first_reads().keep(sha.digest(), ended);
}

}  // namespace impactid
