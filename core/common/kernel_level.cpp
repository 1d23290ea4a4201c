#include "core/common/kernel_level.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <utility>

namespace impactid {
namespace {

constexpr std::array<std::pair<KernelLevel, const char*>, 3> kNames{{
    {KernelLevel::baseline, "baseline"},
    {KernelLevel::x86_64_v3, "x86-64-v3"},
    {KernelLevel::x86_64_v4, "x86-64-v4"},
}};

}  // namespace

const char* to_string(KernelLevel level) {
  for (const auto& [value, name] : kNames) {
    if (value == level) return name;
  }
  return "unknown";
}

std::optional<KernelLevel> kernel_level_from_string(std::string_view name) {
  for (const auto& [value, word] : kNames) {
    if (name == word) return value;
  }
  return std::nullopt;
}

namespace {

// The highest level the processor supports, whatever the build has.
KernelLevel processor_level() {
#if defined(IMPACTID_SINGLE_VERSION) || !defined(__x86_64__)
  // One version of everything, for the flags it was compiled with.
#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512CD__) && \
    defined(__AVX512DQ__) && defined(__AVX512VL__)
  return KernelLevel::x86_64_v4;
#elif defined(__AVX2__) && defined(__FMA__)
  return KernelLevel::x86_64_v3;
#else
  return KernelLevel::baseline;
#endif
#else
  // The features of GCC's x86-64-v3 and v4 that the kernels' code can contain (spelled one by
  // one: clang 14 knows no level names here). libgcc's feature test also checks that the operating
  // system saves the wider registers (XGETBV), not only that the processor has them.
  __builtin_cpu_init();
  const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                  __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
  const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                  __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
                  __builtin_cpu_supports("avx512vl");
  if (v4) return KernelLevel::x86_64_v4;
  if (v3) return KernelLevel::x86_64_v3;
  return KernelLevel::baseline;
#endif
}

}  // namespace

bool kernel_level_built(KernelLevel level) {
  switch (level) {
    case KernelLevel::baseline:
      return true;
    case KernelLevel::x86_64_v3:
#if defined(IMPACTID_HAVE_KERNELS_V3)
      return true;
#else
      return false;
#endif
    case KernelLevel::x86_64_v4:
#if defined(IMPACTID_HAVE_KERNELS_V4)
      return true;
#else
      return false;
#endif
  }
  return false;
}

KernelLevel supported_kernel_level() {
  KernelLevel level = processor_level();
  while (!kernel_level_built(level)) level = static_cast<KernelLevel>(static_cast<int>(level) - 1);
  return level;
}

KernelSelection select_kernels(const char* forced, KernelLevel supported) {
  KernelSelection s;
  s.supported = supported;
  s.level = s.supported;
  if (forced == nullptr || *forced == '\0') return s;
  const std::optional<KernelLevel> level = kernel_level_from_string(forced);
  if (!level) {
    s.error = std::string("IMPACTID_KERNELS = '") + forced +
              "': must be baseline, x86-64-v3 or x86-64-v4";
  } else if (!kernel_level_built(*level)) {
    s.error = std::string("IMPACTID_KERNELS = '") + forced +
              "': this build has no kernels of that level (IMPACTID_KERNEL_LEVELS)";
  } else if (*level > s.supported) {
    s.error = std::string("IMPACTID_KERNELS = '") + forced + "': this processor supports " +
              to_string(s.supported) + " at most";
  } else {
    s.level = *level;
    s.forced = true;
  }
  return s;
}

const KernelSelection& kernel_selection() {
  static const KernelSelection selection =
      select_kernels(std::getenv("IMPACTID_KERNELS"), supported_kernel_level());
  return selection;
}

std::string describe_kernel_selection() {
  const KernelSelection& s = kernel_selection();
  std::string text =
      std::string(to_string(s.level)) + " (processor supports " + to_string(s.supported);
  if (s.forced) text += ", forced by IMPACTID_KERNELS";
  if (!s.error.empty()) text += "; " + s.error;
  return text + ")";
}

}  // namespace impactid
