// Functions compiled once per processor generation, the best one picked when the program starts.
//
// The project builds for baseline x86-64 (no -march=native: a binary runs on any x86-64 host).
// Two kinds of hot code need more than that:
//
// - The scalar implicit step (core/implicit_integrator.cpp, core/tridiagonal.cpp) writes a
//   multiply whose product is only added as std::fma: one rounding instead of two, and a
//   recurrence of one instruction (4 cycles) instead of a multiply and an add (6). The batched
//   kernel (core/batched_simulation.cpp) fuses exactly the same operations, so that its lanes
//   equal the scalar path bit for bit. std::fma is correctly rounded, so the bits are the same
//   on every machine; only its speed differs: one instruction where the processor has FMA3
//   (x86-64-v3: every x86-64 processor since 2013-2015), a C library routine on baseline
//   x86-64, which made the scalar run several times slower (docs/performance.md).
//   IMPACTID_FMA_VERSIONS marks these functions.
// - The batched kernel's loop (run_batch_any) also wants AVX-512 registers, one register per 8
//   lanes: IMPACTID_SIMD_VERSIONS adds x86-64-v4.
//
// GCC's target_clones compiles the marked function once per listed target and resolves the
// symbol at load time from the processor's features. Elsewhere than x86-64 the marks are
// empty: aarch64's baseline already has fused multiply-adds (std::fma is one instruction), and
// the kernel's vector extensions compile to whatever vectors the target has.
//
// IMPACTID_SINGLE_VERSION leaves the marks empty, for a build that runs only where it is built
// (scripts/sanitize, with -march=native): it checks the code, not the dispatch, and compiling
// every kernel once per target under the sanitizers' instrumentation took most of its time.
#pragma once

#if defined(__x86_64__) && !defined(IMPACTID_SINGLE_VERSION)
#define IMPACTID_FMA_VERSIONS __attribute__((target_clones("arch=x86-64-v3", "default")))
#define IMPACTID_SIMD_VERSIONS \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define IMPACTID_FMA_VERSIONS
#define IMPACTID_SIMD_VERSIONS
#endif
