#include "study/formats/first_read.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
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
// free-space object of length 0. Whether it crashes depends on the memory around the copy, and
// a child that survived it would hand over whatever lay there as text: the collections are
// walked here first, as HDF5 walks them, with the checks it lacks. A collection is found by its header, "GCOL",
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

// What this process learnt, by digest: the answers of bytes read before (or nothing, for
// bytes it wrote: those are walked here) and the refusals. Bounded: past kMaxKept entries or
// kMaxKeptBytes of answers it starts again (a forgotten file costs one more child, nothing else).
struct Kept {
  ChildOutcome outcome;
  std::shared_ptr<const Hdf5Answers> answers;  // null: bytes this process wrote
};

class FirstReads {
 public:
  std::optional<Kept> find(const Digest& digest) {
    std::lock_guard lock(mutex_);
    const auto at = kept_.find(digest);
    if (at == kept_.end()) return std::nullopt;
    return at->second;
  }
  void keep(const Digest& digest, Kept kept) {
    std::lock_guard lock(mutex_);
    const std::size_t size = kept.answers ? kept.answers->size_in_bytes() : 0;
    if (size > kMaxKeptBytes) return;  // read again if asked again
    if (kept_.size() >= kMaxKept || bytes_ + size > kMaxKeptBytes) {
      kept_.clear();
      bytes_ = 0;
    }
    bytes_ += size;
    kept_.insert_or_assign(digest, std::move(kept));
  }

 private:
  static constexpr std::size_t kMaxKept = 4096;
  static constexpr std::size_t kMaxKeptBytes = std::size_t{64} << 20;
  std::mutex mutex_;
  std::unordered_map<Digest, Kept> kept_;
  std::size_t bytes_ = 0;
};

FirstReads& first_reads() {
  static FirstReads reads;
  return reads;
}

constexpr const char* kWhatToDo = " (the file is damaged; use a backup or run it again)";

// The child's exit status when its answers could not be written to the pipe.
constexpr int kAnswersNotSent = 70;

}  // namespace

std::shared_ptr<const Hdf5Answers> first_read(const std::filesystem::path& path,
                                               const std::function<Hdf5Answers()>& walk) {
  Digest digest;
  double seconds = kFirstReadSeconds;
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
      digest = sha.digest();
    }
  }
  const auto walk_here = [&] { return std::make_shared<const Hdf5Answers>(walk()); };
  const auto refuse = [&](const std::string& why) {
    return Hdf5Error(path.string() + ": damaged: " + why +
                     "; it was read in a separate process, so nothing else is lost" + kWhatToDo);
  };
  std::optional<Kept> kept = digest.empty() ? std::nullopt : first_reads().find(digest);
  if (!kept) {
    // The file cannot be read (missing, empty, unreadable: the walk says why) or is new here.
    Kept fresh;
    fresh.outcome = run_in_child(
        [&](int output) {
          if (!write_output(output, walk().serialized())) _exit(kAnswersNotSent);
        },
        seconds);
    if (fresh.outcome.kind == ChildOutcome::Kind::not_run) return walk_here();  // no child
    if (fresh.outcome.kind == ChildOutcome::Kind::ended) {
      try {
        fresh.answers = std::make_shared<const Hdf5Answers>(
            Hdf5Answers::parse(std::move(fresh.outcome.output)));
        fresh.outcome.output.clear();
      } catch (const std::runtime_error& e) {
        throw refuse(std::string("its reader's answers were unreadable (") + e.what() + ")");
      }
    }
    if (!digest.empty()) first_reads().keep(digest, fresh);
    kept = std::move(fresh);
  }
  switch (kept->outcome.kind) {
    case ChildOutcome::Kind::crashed:
      throw refuse(
          "reading it crashes HDF5 (" +
          (kept->outcome.signal ? std::string(strsignal(kept->outcome.signal))
                                : "exit status " + std::to_string(kept->outcome.exit_status)) +
          ")");
    case ChildOutcome::Kind::timed_out:
      throw refuse("reading it did not end within " + std::to_string(std::lround(seconds)) + " s");
    case ChildOutcome::Kind::ended:
    case ChildOutcome::Kind::not_run:
      break;
  }
  return kept->answers ? kept->answers : walk_here();
}

void remember_readable(std::span<const char> image) {
  if (image.size() > kRememberedImageBytes) return;
  Sha256 sha;
  sha.add(image.data(), image.size());
  Kept written;
  written.outcome.kind = ChildOutcome::Kind::ended;
  first_reads().keep(sha.digest(), written);
}

}  // namespace impactid
