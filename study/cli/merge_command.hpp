// `impactid merge SHARD.h5... --output FILE`: the results files of a plan's shards
// (`impactid run --shard K/N`, study/studies/shard.hpp) into the one file a single run of the plan
// writes, checked by study/io/shard_merge.hpp, with the plan's practical range computed over the
// whole table. Written atomically; an existing file that is not a results file is left
// untouched. Exit status 2 when the shards do not fit together (the message names them).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace impactid {

std::function<int()> add_merge_command(CLI::App& app);

}  // namespace impactid
