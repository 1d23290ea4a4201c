// The kernel level (core/common/kernel_level.hpp): the one chosen is the highest that the processor
// supports and the build has, read here from /proc/cpuinfo (the kernel's word, not libgcc's
// feature test the selection uses); IMPACTID_KERNELS forces a level, and refuses one the processor
// or the build lacks. That every level gives the same numbers is checked by the batched tests run
// again at each level (tests/CMakeLists.txt: kernel_levels.*) and by kernel_levels_test.py.
#include "core/common/kernel_level.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace impactid {
namespace {

// The flags of the first processor in /proc/cpuinfo (empty where there is none).
std::set<std::string> cpu_flags() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("flags", 0) != 0) continue;
    std::istringstream words(line.substr(line.find(':') + 1));
    std::set<std::string> flags;
    for (std::string w; words >> w;) flags.insert(w);
    return flags;
  }
  return {};
}

// x86-64-v3 and v4 as GCC defines them, in the features the kernels' code may contain.
KernelLevel level_from_flags(const std::set<std::string>& f) {
  const auto has = [&](const char* flag) { return f.count(flag) > 0; };
  const bool v3 = has("avx2") && has("fma") && has("bmi1") && has("bmi2");
  const bool v4 = v3 && has("avx512f") && has("avx512bw") && has("avx512cd") && has("avx512dq") &&
                  has("avx512vl");
  return v4 ? KernelLevel::x86_64_v4 : v3 ? KernelLevel::x86_64_v3 : KernelLevel::baseline;
}

TEST(KernelLevel, ChosenLevelIsTheHighestTheProcessorSupportsAndTheBuildHas) {
  const std::set<std::string> flags = cpu_flags();
  if (flags.empty()) GTEST_SKIP() << "no /proc/cpuinfo flags to check against";
  KernelLevel expected = level_from_flags(flags);
  while (!kernel_level_built(expected)) {
    expected = static_cast<KernelLevel>(static_cast<int>(expected) - 1);
  }
  const KernelSelection& s = kernel_selection();
  EXPECT_EQ(s.supported, expected) << "supported " << to_string(s.supported) << ", /proc/cpuinfo "
                                   << to_string(level_from_flags(flags));
  EXPECT_TRUE(s.error.empty()) << s.error;
  const char* forced = std::getenv("IMPACTID_KERNELS");
  if (forced != nullptr && *forced != '\0') {
    EXPECT_TRUE(s.forced);
    EXPECT_STREQ(to_string(s.level), forced);
  } else {
    // The defect this guards against: a dispatch that silently ran a lower level (GCC 12's
    // target_clones resolver picked baseline on AMD Zen 3).
    EXPECT_FALSE(s.forced);
    EXPECT_EQ(s.level, expected) << "runs " << to_string(s.level) << " on a processor with "
                                 << to_string(expected);
  }
}

TEST(KernelLevel, NamesRoundTrip) {
  for (KernelLevel level :
       {KernelLevel::baseline, KernelLevel::x86_64_v3, KernelLevel::x86_64_v4}) {
    EXPECT_EQ(kernel_level_from_string(to_string(level)), level);
  }
  EXPECT_FALSE(kernel_level_from_string("avx2"));
  EXPECT_FALSE(kernel_level_from_string("X86-64-V3"));
}

TEST(KernelLevel, UnsetOrEmptyRunsTheSupportedLevel) {
  for (const char* forced : {static_cast<const char*>(nullptr), ""}) {
    const KernelSelection s = select_kernels(forced, KernelLevel::x86_64_v3);
    EXPECT_EQ(s.level, KernelLevel::x86_64_v3);
    EXPECT_FALSE(s.forced);
    EXPECT_TRUE(s.error.empty());
  }
}

TEST(KernelLevel, ForcesALowerLevel) {
  const KernelSelection s = select_kernels("baseline", KernelLevel::x86_64_v3);
  EXPECT_EQ(s.level, KernelLevel::baseline);
  EXPECT_TRUE(s.forced);
  EXPECT_TRUE(s.error.empty());
}

TEST(KernelLevel, RefusesALevelAboveTheProcessorsAndAnUnknownName) {
  const KernelSelection above = select_kernels("x86-64-v4", KernelLevel::x86_64_v3);
  EXPECT_EQ(above.level, KernelLevel::x86_64_v3);  // never one whose instructions would fault
  EXPECT_FALSE(above.forced);
  EXPECT_NE(above.error.find("IMPACTID_KERNELS = 'x86-64-v4'"), std::string::npos) << above.error;
  // A build for one machine (scripts/sanitize) may lack v4's kernels: then that is the reason
  // given, checked before the processor's limit.
  const char* reason = kernel_level_built(KernelLevel::x86_64_v4)
                           ? "this processor supports x86-64-v3 at most"
                           : "this build has no kernels of that level";
  EXPECT_NE(above.error.find(reason), std::string::npos) << above.error;

  const KernelSelection unknown = select_kernels("avx2", KernelLevel::x86_64_v4);
  EXPECT_EQ(unknown.level, KernelLevel::x86_64_v4);
  EXPECT_NE(unknown.error.find("'avx2': must be baseline, x86-64-v3 or x86-64-v4"),
            std::string::npos)
      << unknown.error;
}

TEST(KernelLevel, DescriptionNamesWhatRunsAndWhatIsSupported) {
  const std::string text = describe_kernel_selection();
  EXPECT_NE(text.find(to_string(kernel_level())), std::string::npos) << text;
  EXPECT_NE(text.find(std::string("processor supports ") + to_string(supported_kernel_level())),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace impactid
