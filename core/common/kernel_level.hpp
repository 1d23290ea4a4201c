// Which processor generation's kernels run: chosen once, when first asked, from what the
// processor supports, or forced with the environment variable IMPACTID_KERNELS.
//
// The project builds for baseline x86-64 (no -march=native: a binary runs on any x86-64 host),
// and compiles its hot code once more per processor generation it cares for:
// - x86-64-v3 (AVX2 and FMA3; every x86-64 processor since 2013-2015): the batched kernels on
//   256-bit registers, and the scalar steps' fused multiply-adds as one instruction;
// - x86-64-v4 (AVX-512): the batched kernels on 512-bit registers.
// On `baseline` no batched kernel runs (every point goes through the scalar stepper, which gives
// the same numbers) and std::fma is the C library's routine.
//
// Why not GCC's target_clones: its resolver, run by the dynamic loader, picked the baseline
// version on AMD Zen 3 (AVX2, FMA) for "arch=x86-64-v3", "avx2" and even "arch=x86-64-v2",
// while __builtin_cpu_supports said yes in the same process: the kernels ran many times
// slower, and nothing said so. The choice here is made by the program after
// __builtin_cpu_init, can be printed (`impactid --version`), forced, and tested on the machine
// that runs it (tests/kernel_level_test.cpp).
//
// Every level gives the same numbers, bit for bit (the kernels perform the scalar path's
// operations; tests/kernel_level_test.cpp runs each level the processor has and compares).
//
// Thread safety: the selection is made once (a function-local static) and read-only after.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace impactid {

enum class KernelLevel {
  baseline,   ///< x86-64 as of 2003: scalar steps only, std::fma in software
  x86_64_v3,  ///< AVX2 and FMA3: batched kernels on 256-bit registers
  x86_64_v4,  ///< AVX-512 (F, BW, CD, DQ, VL): batched kernels on 512-bit registers
};
/// "baseline", "x86-64-v3", "x86-64-v4": the names IMPACTID_KERNELS takes.
const char* to_string(KernelLevel level);
std::optional<KernelLevel> kernel_level_from_string(std::string_view name);

/// Whether this build has the level's kernels (core/CMakeLists.txt: IMPACTID_KERNEL_LEVELS;
/// baseline always).
bool kernel_level_built(KernelLevel level);

/// The highest level that the processor supports and the build has.
KernelLevel supported_kernel_level();

struct KernelSelection {
  KernelLevel level = KernelLevel::baseline;      ///< what runs
  KernelLevel supported = KernelLevel::baseline;  ///< supported_kernel_level()
  bool forced = false;                            ///< IMPACTID_KERNELS set (and valid)
  /// Non-empty when IMPACTID_KERNELS names no level, or one above what the processor supports
  /// (its instructions would fault): then `level` is `supported`, and the programs refuse to
  /// start with this message.
  std::string error;
};

/// What IMPACTID_KERNELS = `forced` (null or empty: unset) selects on a processor and build
/// whose highest level is `supported`.
KernelSelection select_kernels(const char* forced, KernelLevel supported);

/// The selection, made at the first call from IMPACTID_KERNELS (unset or empty: the supported
/// level) and kept for the life of the process.
const KernelSelection& kernel_selection();

/// kernel_selection().level: which kernels run.
inline KernelLevel kernel_level() {
  return kernel_selection().level;
}

/// One line for a person: "x86-64-v4 (processor supports x86-64-v4)", with ", forced by
/// IMPACTID_KERNELS" when it is.
std::string describe_kernel_selection();

}  // namespace impactid
