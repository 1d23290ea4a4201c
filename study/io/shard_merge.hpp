// `impactid merge`'s core: the results files of a plan's shards (study/studies/shard.hpp) put back
// into the one table a single run of the plan writes.
//
// Checked before anything is written, each failure a MergeError naming the file(s) and the
// shard(s):
//   - every file is a readable results file that records its shard (an unsharded results file
//     counts as shard 0/1);
//   - every file carries the same plan: the same embedded text, the same plan_sha256, and that
//     hash is the text's (a file whose plan was edited afterwards is refused); the same grid,
//     columns, program version and git revision (another build could compute other numbers);
//   - together the shards cover every point exactly once: a missing shard is named with the
//     number of its points and the first of them, a duplicated one with both files;
//   - every shard is finished (an interrupted shard is named, with how to resume it).
// The merged table takes each point from the file of the shard that owns it: status, every
// parameter and indicator, bit for bit. Root attributes are the single run's: the shard
// attributes are dropped, `threads` is the largest of the shards', `run_wall_time_s` their sum
// (the computing time spent in all), `date` the merge's.
//
// Memory: the merged table plus one shard's file at a time.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "study/io/results_file.hpp"
#include "study/studies/shard.hpp"

namespace impactid {

struct MergeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct MergedShards {
  StudyResults results;  ///< as a single run of the plan writes it (date and timing aside)
  ShardMark first;       ///< the first file's shard record (plan file, shard count)
  long files = 0;
};

/// Reads, checks and merges the files. Throws MergeError (bad input) as above, Hdf5Error never
/// (an unreadable file is a MergeError naming it).
MergedShards merge_shards(const std::vector<std::filesystem::path>& files);

}  // namespace impactid
