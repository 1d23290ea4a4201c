#include "study/formats/first_read.hpp"

#include <openssl/evp.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

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

// Empty when the file cannot be read: the child (and then the reader) says why.
Digest digest_of_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  Sha256 sha;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    sha.add(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  return in.bad() ? Digest() : sha.digest();
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

}  // namespace

void check_first_read(const std::filesystem::path& path,
                      const std::function<void()>& read_everything) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  const double seconds = kFirstReadSeconds + (ec ? 0.0 : static_cast<double>(size) / 1e7);
  const Digest digest = digest_of_file(path);
  std::optional<ChildOutcome> outcome = digest.empty() ? std::nullopt : first_reads().find(digest);
  if (!outcome) {
    outcome = run_in_child(read_everything, seconds);
    if (!digest.empty() && outcome->kind != ChildOutcome::Kind::not_run) {
      first_reads().keep(digest, *outcome);
    }
  }
  const std::string advice =
      "; it was read first in a separate process, so nothing else is lost (the file is damaged; "
      "use a backup or run it again)";
  switch (outcome->kind) {
    case ChildOutcome::Kind::crashed:
      throw Hdf5Error(path.string() + ": damaged: reading it crashes HDF5 (" +
                      (outcome->signal ? std::string(strsignal(outcome->signal))
                                       : "exit status " + std::to_string(outcome->exit_status)) +
                      ")" + advice);
    case ChildOutcome::Kind::timed_out:
      throw Hdf5Error(path.string() + ": damaged: reading it did not end within " +
                      std::to_string(std::lround(seconds)) + " s" + advice);
    case ChildOutcome::Kind::ended:
    case ChildOutcome::Kind::not_run:
      return;
  }
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
