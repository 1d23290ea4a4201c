#include "study/io/shard_merge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

namespace impactid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string file_text(const std::filesystem::path& file, const ShardMark& mark) {
  return file.string() + " (shard " + to_string(mark.shard) + ")";
}

// "5 points (first: 16, 17, 18)"
std::string points_text(const std::vector<long>& points) {
  std::string text =
      std::to_string(points.size()) + (points.size() == 1 ? " point" : " points") + " (first: ";
  for (std::size_t k = 0; k < std::min<std::size_t>(points.size(), 3); ++k) {
    text += (k ? ", " : "") + std::to_string(points[k]);
  }
  return text + (points.size() > 3 ? ", ...)" : ")");
}

std::vector<std::string> column_names(const StudyResults& r) {
  std::vector<std::string> names;
  for (const ResultColumn& c : r.parameters) names.push_back("parameter " + c.name);
  for (const ResultColumn& c : r.indicators) names.push_back("indicator " + c.name);
  return names;
}

// Why two files of shards cannot be merged, or "" when they can: the same plan, grid, columns
// and program.
std::string difference(const StudyResults& a, const ShardMark& ma, const StudyResults& b,
                       const ShardMark& mb) {
  if (a.plan_text != b.plan_text || ma.plan_sha256 != mb.plan_sha256) {
    return "come from different plans (plan_sha256 " + ma.plan_sha256.substr(0, 12) + "... and " +
           mb.plan_sha256.substr(0, 12) + "...)";
  }
  if (a.impactid_version != b.impactid_version || a.git_revision != b.git_revision) {
    return "were computed by different builds of impactid (" + a.impactid_version + " " +
           a.git_revision + " and " + b.impactid_version + " " + b.git_revision +
           "); resume the odd ones with one build";
  }
  bool same_grid = a.dimensions.size() == b.dimensions.size();
  for (std::size_t d = 0; same_grid && d < a.dimensions.size(); ++d) {
    same_grid = a.dimensions[d].name == b.dimensions[d].name &&
                a.dimensions[d].values == b.dimensions[d].values;
  }
  if (!same_grid) return "have different grids";
  if (column_names(a) != column_names(b)) return "have different columns";
  return "";
}

}  // namespace

MergedShards merge_shards(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) throw MergeError("no shard files given");
  MergedShards merged;
  StudyResults& out = merged.results;
  std::vector<long> owner;  // per point: the file that computed it, −1 none yet
  std::vector<ShardMark> marks;
  for (std::size_t f = 0; f < files.size(); ++f) {
    const std::filesystem::path& file = files[f];
    StudyResults r;
    try {
      r = read_results(file);
    } catch (const std::exception& e) {
      throw MergeError(e.what());
    }
    ShardMark mark;
    try {
      const std::optional<ShardMark> recorded = shard_mark(r);
      mark = recorded ? *recorded : ShardMark{{0, 1}, kShardWindow, "", sha256_hex(r.plan_text)};
    } catch (const ShardError& e) {
      throw MergeError(file.string() + ": " + e.what());
    }
    if (r.study_kind != "grid" && r.study_kind != "list") {
      throw MergeError(file.string() + ": a " + r.study_kind +
                       " study's file; only grid and list studies are run in shards");
    }
    if (mark.plan_sha256 != sha256_hex(r.plan_text)) {
      throw MergeError(file.string() + ": plan_sha256 = " + mark.plan_sha256 +
                       " is not the SHA-256 of the plan it carries (" + sha256_hex(r.plan_text) +
                       "): the file was changed after its run");
    }
    if (mark.window != kShardWindow) {
      throw MergeError(file.string() + ": shard_window = " + std::to_string(mark.window) +
                       ", but this impactid cuts shards in windows of " +
                       std::to_string(kShardWindow) +
                       " points; merge with the impactid that computed the shards");
    }
    if (f == 0) {
      out = r;
      unmark_shard(out);
      std::fill(out.status.begin(), out.status.end(), kStatusNotDone);
      for (auto* columns : {&out.parameters, &out.indicators}) {
        for (ResultColumn& c : *columns) std::fill(c.values.begin(), c.values.end(), kNaN);
      }
      out.threads = 0;
      out.wall_time_s = 0;
      owner.assign(r.status.size(), -1);
      merged.first = mark;
    } else if (const std::string why = difference(out, marks.front(), r, mark); !why.empty()) {
      throw MergeError(files.front().string() + " and " + file.string() + " " + why);
    }

    const std::vector<long> points = shard_points(r.points_total(), mark.shard);
    std::vector<long> not_done;
    for (const long i : points) {
      if (r.status[static_cast<std::size_t>(i)] == kStatusNotDone) not_done.push_back(i);
    }
    if (!not_done.empty()) {
      throw MergeError(file_text(file, mark) + " is not finished: " + points_text(not_done) +
                       " of its " + std::to_string(points.size()) +
                       " are not done; finish it with impactid run PLAN --shard " +
                       to_string(mark.shard) + " --resume --output " + file.string());
    }
    for (const long i : points) {
      const long other = owner[static_cast<std::size_t>(i)];
      if (other < 0) continue;
      std::vector<long> both;
      for (const long j : points) {
        if (owner[static_cast<std::size_t>(j)] == other) both.push_back(j);
      }
      const std::string what = marks[static_cast<std::size_t>(other)].shard == mark.shard
                                   ? "shard " + to_string(mark.shard) + " is given twice: "
                                   : "shards overlap: ";
      throw MergeError(what +
                       file_text(files[static_cast<std::size_t>(other)],
                                 marks[static_cast<std::size_t>(other)]) +
                       " and " + file_text(file, mark) + " both hold " + points_text(both));
    }
    for (const long i : points) {
      const auto k = static_cast<std::size_t>(i);
      owner[k] = static_cast<long>(f);
      out.status[k] = r.status[k];
      for (std::size_t c = 0; c < out.parameters.size(); ++c) {
        out.parameters[c].values[k] = r.parameters[c].values[k];
      }
      for (std::size_t c = 0; c < out.indicators.size(); ++c) {
        out.indicators[c].values[k] = r.indicators[c].values[k];
      }
    }
    out.threads = std::max(out.threads, r.threads);
    out.wall_time_s += r.wall_time_s;
    marks.push_back(mark);
  }

  std::vector<long> missing;
  for (std::size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) missing.push_back(static_cast<long>(i));
  }
  if (!missing.empty()) {
    const long count = marks.front().shard.count;
    const bool one_split = std::all_of(marks.begin(), marks.end(),
                                       [&](const ShardMark& m) { return m.shard.count == count; });
    std::string what;
    if (one_split) {
      std::set<long> absent;
      for (const long i : missing) absent.insert(shard_of_point(i, count));
      for (const long k : absent) {
        what += std::string(what.empty() ? "" : ", ") + to_string(Shard{k, count});
      }
      what = (absent.size() == 1 ? "shard " : "shards ") + what +
             (absent.size() == 1 ? " is" : " are") + " missing: ";
    } else {
      what = "the shards do not cover every point: ";
    }
    throw MergeError(what + points_text(missing) + " of " + std::to_string(owner.size()) +
                     " are in none of the " + std::to_string(files.size()) + " files");
  }
  merged.files = static_cast<long>(files.size());
  return merged;
}

}  // namespace impactid
