// Code compiled once per processor generation, the one that runs chosen by the program
// (core/common/kernel_level.hpp), not by the compiler's resolver.
//
// Two kinds of hot code need more than baseline x86-64:
// - The scalar implicit step (core/methods/implicit_integrator.cpp, core/algebra/tridiagonal.cpp)
//   writes a multiply whose product is only added as std::fma: one rounding instead of two, and
//   a recurrence of one instruction (4 cycles) instead of a multiply and an add (6). The batched
//   kernels fuse exactly the same operations, so that their lanes equal the scalar path bit for
//   bit. std::fma is correctly rounded, so the bits are the same on every machine; only its speed
//   differs: one instruction where the processor has FMA3 (x86-64-v3), a C library routine on
//   baseline x86-64, which made the scalar run several times slower (docs/performance.md).
//   with_fma_versions() below compiles such a body twice and runs the one the level allows.
// - The batched kernels (core/batch/*_kernel.cpp) are compiled once per level into their own
//   object files, each in its own namespace with its own register width
//   (core/batch/simd_lanes.hpp, core/batch/batch_kernels.hpp).
//
// IMPACTID_SINGLE_VERSION compiles one version, for the flags of the build (scripts/sanitize,
// with -march=native: it checks the code, not the dispatch, and clang has no GCC target pragmas).
#pragma once

#include "core/common/kernel_level.hpp"

#if defined(__x86_64__) && !defined(IMPACTID_SINGLE_VERSION)
#define IMPACTID_FMA_TARGET __attribute__((target("arch=x86-64-v3")))
#define IMPACTID_AVX512_TARGET __attribute__((target("arch=x86-64-v4")))
#else
#define IMPACTID_FMA_TARGET
#define IMPACTID_AVX512_TARGET
#endif

namespace impactid {

// `body` with every call it makes inlined (flatten), compiled for x86-64-v3 or for baseline.
template <class Body>
__attribute__((flatten)) IMPACTID_FMA_TARGET void run_with_fma_instructions(const Body& body) {
  body();
}
template <class Body>
__attribute__((flatten)) void run_without_fma_instructions(const Body& body) {
  body();
}

/// Runs body() compiled with FMA3 instructions when the kernel level has them, else compiled
/// for baseline x86-64 (std::fma then calls the C library). The same numbers either way.
template <class Body>
[[gnu::always_inline]] inline void with_fma_versions(const Body& body) {
  if (kernel_level() >= KernelLevel::x86_64_v3) {
    run_with_fma_instructions(body);
  } else {
    run_without_fma_instructions(body);
  }
}

}  // namespace impactid
