#include "study/studies/shard.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string_view>

namespace impactid {
namespace {

constexpr const char* kShardAttribute = "shard";
constexpr const char* kWindowAttribute = "shard_window";
constexpr const char* kPlanFileAttribute = "shard_plan_file";
constexpr const char* kPlanHashAttribute = "plan_sha256";

// A whole non-negative number, the whole text and nothing else.
std::optional<long> whole_number(std::string_view text) {
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || text.empty() || value < 0) {
    return std::nullopt;
  }
  return value;
}

const std::string* text_attribute(const StudyResults& r, const std::string& name) {
  for (const auto& [key, value] : r.text_attributes) {
    if (key == name) return &value;
  }
  return nullptr;
}

const double* numeric_attribute(const StudyResults& r, const std::string& name) {
  for (const auto& [key, value] : r.numeric_attributes) {
    if (key == name) return &value;
  }
  return nullptr;
}

}  // namespace

std::string to_string(Shard shard) {
  return std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

Shard parse_shard(const std::string& text, const std::string& option) {
  const std::size_t slash = text.find('/');
  const auto bad = [&](const std::string& why) {
    return ShardError(option + " " + text + ": " + why);
  };
  if (slash == std::string::npos) throw bad("expected K/N, the K-th of N shards (0 <= K < N)");
  const auto k = whole_number(std::string_view(text).substr(0, slash));
  const auto n = whole_number(std::string_view(text).substr(slash + 1));
  if (!k || !n) throw bad("K and N must be whole numbers, K/N with 0 <= K < N");
  if (*n < 1) throw bad("N must be at least 1");
  if (*k >= *n) throw bad("K must lie in 0.." + std::to_string(*n - 1) + " (shards count from 0)");
  return {*k, *n};
}

std::optional<Shard> slurm_array_shard(const std::function<const char*(const char*)>& environment) {
  const char* id_text = environment("SLURM_ARRAY_TASK_ID");
  if (!id_text) return std::nullopt;
  const auto read = [&](const char* name, const char* fallback) -> long {
    const char* value = environment(name);
    if (!value) value = fallback;
    if (!value) {
      throw ShardError(std::string("SLURM_ARRAY_TASK_ID is set (") + id_text + ") but " + name +
                       " is not: cannot tell this task's shard; give --shard K/N");
    }
    const auto number = whole_number(value);
    if (!number) {
      throw ShardError(std::string(name) + "=" + value +
                       ": not a whole number (Slurm's array "
                       "variables); give --shard K/N");
    }
    return *number;
  };
  const long id = read("SLURM_ARRAY_TASK_ID", nullptr);
  const long min = read("SLURM_ARRAY_TASK_MIN", nullptr);
  const long count = read("SLURM_ARRAY_TASK_COUNT", nullptr);
  const long step = read("SLURM_ARRAY_TASK_STEP", "1");
  if (count < 1 || step < 1 || id < min || (id - min) % step != 0 || (id - min) / step >= count) {
    throw ShardError("SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " with SLURM_ARRAY_TASK_MIN=" +
                     std::to_string(min) + ", SLURM_ARRAY_TASK_STEP=" + std::to_string(step) +
                     " and SLURM_ARRAY_TASK_COUNT=" + std::to_string(count) +
                     ": the array's indices are not MIN, MIN+STEP, ..., so they do not number "
                     "the shards; use --array=0-(N-1), or give --shard K/N");
  }
  return Shard{(id - min) / step, count};
}

long shard_of_point(long index, long shard_count) {
  return (index / kShardWindow) % shard_count;
}

std::vector<long> shard_points(long total, Shard shard) {
  std::vector<long> points;
  for (long first = shard.index * kShardWindow; first < total;
       first += shard.count * kShardWindow) {
    for (long i = first; i < std::min(total, first + kShardWindow); ++i) points.push_back(i);
  }
  return points;
}

std::filesystem::path shard_file(const std::filesystem::path& file, Shard shard) {
  const int width = static_cast<int>(std::to_string(shard.count - 1).size());
  char number[48];
  std::snprintf(number, sizeof number, ".shard-%0*ld-of-%ld", width, shard.index, shard.count);
  std::filesystem::path result = file.parent_path() / file.stem();
  result += number;
  result += file.extension();
  return result;
}

std::string sha256_hex(const std::string& text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256 (OpenSSL EVP_Digest) failed");
  }
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    char pair[3];
    std::snprintf(pair, sizeof pair, "%02x", digest[i]);
    hex += pair;
  }
  return hex;
}

void mark_shard(StudyResults& results, Shard shard, const std::filesystem::path& plan_file) {
  unmark_shard(results);
  results.text_attributes.emplace_back(kShardAttribute, to_string(shard));
  results.numeric_attributes.emplace_back(kWindowAttribute, static_cast<double>(kShardWindow));
  results.text_attributes.emplace_back(kPlanFileAttribute,
                                       std::filesystem::absolute(plan_file).string());
  results.text_attributes.emplace_back(kPlanHashAttribute, sha256_hex(results.plan_text));
}

std::optional<ShardMark> shard_mark(const StudyResults& results) {
  const std::string* shard = text_attribute(results, kShardAttribute);
  if (!shard) return std::nullopt;
  ShardMark mark;
  mark.shard = parse_shard(*shard, "attribute shard =");
  const double* window = numeric_attribute(results, kWindowAttribute);
  const std::string* plan_file = text_attribute(results, kPlanFileAttribute);
  const std::string* hash = text_attribute(results, kPlanHashAttribute);
  if (!window || !plan_file || !hash) {
    throw ShardError(std::string("a shard's file needs the attributes ") + kWindowAttribute + ", " +
                     kPlanFileAttribute + " and " + kPlanHashAttribute +
                     " beside shard; one is missing");
  }
  if (!(*window >= 1) || *window != std::floor(*window)) {
    throw ShardError(std::string("attribute ") + kWindowAttribute + " = " +
                     std::to_string(*window) + ": not a whole number of points");
  }
  mark.window = static_cast<long>(*window);
  mark.plan_file = *plan_file;
  mark.plan_sha256 = *hash;
  return mark;
}

void unmark_shard(StudyResults& results) {
  const auto is_shard_text = [](const auto& a) {
    return a.first == kShardAttribute || a.first == kPlanFileAttribute ||
           a.first == kPlanHashAttribute;
  };
  std::erase_if(results.text_attributes, is_shard_text);
  std::erase_if(results.numeric_attributes,
                [](const auto& a) { return a.first == kWindowAttribute; });
}

}  // namespace impactid
