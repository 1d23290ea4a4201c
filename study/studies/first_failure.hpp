// The first exception thrown by any iteration of an OpenMP loop, carried out of the parallel
// region and rethrown after it. An exception may not leave a parallel region (the program
// would terminate: issue 38 found a checkpoint's write error aborting a sweep that way), so
// each iteration runs through run(), and once one has failed the others are skipped.
//
// Thread safety: run() and failed() from any thread; rethrow_if_failed() after the region.
#pragma once

#include <atomic>
#include <exception>
#include <mutex>

namespace impactid {

class FirstFailure {
 public:
  /// Runs fn unless an earlier iteration failed; keeps what it throws if it is the first.
  template <class Fn>
  void run(Fn&& fn) noexcept {
    if (failed()) return;
    try {
      fn();
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);
    }
  }

  bool failed() const { return failed_.load(std::memory_order_relaxed); }

  /// Rethrows the first exception, if any; after the parallel region.
  void rethrow_if_failed() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

}  // namespace impactid
