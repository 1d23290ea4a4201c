// Splitting a grid or list plan between independent processes, `impactid run --shard K/N` (by
// hand, or one task of a Slurm job array each), and what a shard's results file records so that
// `impactid merge` (study/io/shard_merge.hpp) can check the pieces and put them back together.
//
// Which points a shard computes: the flat point indices (study/plan/point_set.hpp) are cut into
// windows of kShardWindow consecutive points, the unit of work of the sweep and its batched
// kernel, and window w belongs to shard w mod N. Interleaved rather than in N blocks, because
// cost is not uniform along the grid (unstable points stop early, a finer mesh costs more): a
// block of the grid could be all cheap or all dear, a comb over it samples every region. Whole
// windows, so that a shard's batches are the single run's batches.
//
// A shard's file is an ordinary results file of the whole grid (points of other shards are not
// done: status −1, NaN) with four more root attributes, written after the study's own:
//   shard             string   "K/N"
//   shard_window      float64  kShardWindow when the shard was written (the merge checks it)
//   shard_plan_file   string   the plan file's absolute path (the merge reads its scene and
//                              model files through it, for the practical range)
//   plan_sha256       string   SHA-256 of the embedded plan text, lower-case hex
// `impactid run --resume` on a shard file continues that shard only.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/batch/batched_simulation.hpp"
#include "study/studies/study_results.hpp"

namespace impactid {

inline constexpr long kShardWindow = kBatchLanes;

/// Bad input about sharding (a --shard value, a Slurm variable, a shard file's attributes).
struct ShardError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Shard `index` of `count`, 0 <= index < count. {0, 1} is the whole plan.
struct Shard {
  long index = 0;
  long count = 1;
  friend bool operator==(const Shard&, const Shard&) = default;
};

/// "K/N"
std::string to_string(Shard shard);

/// Parses "K/N" (0 <= K < N, integers). Throws ShardError naming `option` and the value.
Shard parse_shard(const std::string& text, const std::string& option = "--shard");

/// The shard of a Slurm array task: K = (SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN) /
/// SLURM_ARRAY_TASK_STEP (1 when unset), N = SLURM_ARRAY_TASK_COUNT. nullopt when
/// SLURM_ARRAY_TASK_ID is unset (not an array job). Throws ShardError naming the variable and
/// its value when one is missing or malformed, or when the array's indices are not evenly
/// spaced (`--array=1,5,7`: then give --shard explicitly). `environment` is getenv().
std::optional<Shard> slurm_array_shard(const std::function<const char*(const char*)>& environment);

/// The shard that computes flat point `index`.
long shard_of_point(long index, long shard_count);
/// The flat indices of a shard's points among `total`, ascending.
std::vector<long> shard_points(long total, Shard shard);

/// The default file of a shard: "<stem>.shard-K-of-N<ext>" beside `file`, K zero-padded to
/// the width of N−1 so that the shards sort in order ("grid.shard-03-of-32.h5").
std::filesystem::path shard_file(const std::filesystem::path& file, Shard shard);

/// SHA-256 of `text`, 64 lower-case hex digits (OpenSSL).
std::string sha256_hex(const std::string& text);

/// What a shard's file records about itself (the attributes above).
struct ShardMark {
  Shard shard;
  long window = kShardWindow;
  std::string plan_file;
  std::string plan_sha256;
};

/// Records the shard attributes (above) in `results`, replacing any earlier ones.
void mark_shard(StudyResults& results, Shard shard, const std::filesystem::path& plan_file);
/// What a results table says about its shard: nullopt for an unsharded file. Throws ShardError
/// for a missing or malformed shard attribute.
std::optional<ShardMark> shard_mark(const StudyResults& results);
/// Removes the shard attributes, leaving the table a single run would have.
void unmark_shard(StudyResults& results);

}  // namespace impactid
