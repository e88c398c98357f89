// Merging the output directories of a batch's shards.
#include <filesystem>
#include <optional>

#include "batch_setup.h"
#include "batch_store.h"
#include "skelgrasp/common/directory_lock.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/evaluation/batch.h"

namespace skelgrasp::evaluation {

void mergeBatches(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  if (shard_dirs.empty()) throw InvalidArgument("merge: no shard directories");
  // Everything is checked before out_dir is touched.
  std::optional<nlohmann::json> options;
  std::string options_from;
  for (const auto& dir : shard_dirs) {
    if (!std::filesystem::exists(dir + "/runs.jsonl"))
      throw IoError(dir, "no runs.jsonl (not a batch output)");
    if (const auto holder = lockHolder(dir)) {
      throw IoError(dir, (*holder > 0 ? "is in use by process " + std::to_string(*holder)
                                      : std::string("is in use by another process")) +
                             " (its evaluate has not finished)");
    }
    const auto shard_options = internal::readBatchOptions(dir);
    if (!shard_options) {
      log().warn("{}: no batch.json (written by an older skelgrasp): its options cannot be checked",
                 dir);
    } else if (!options) {
      options = shard_options;
      options_from = dir;
    } else if (const auto differ = internal::describeDifferences(*options, *shard_options);
               !differ.empty()) {
      throw InvalidArgument(dir + ": was run with other options than " + options_from + " (" +
                            differ + "); shards of one batch must share them");
    }
  }
  internal::BatchRecords merged;
  for (const auto& dir : shard_dirs) {
    auto shard = internal::loadBatchRecords(dir);
    for (auto& [key, run] : shard.runs) {
      if (merged.runs.count(key)) continue;  // the first shard that has a run wins
      merged.runs[key] = std::move(run);
      if (shard.results.count(key)) merged.results[key] = std::move(shard.results[key]);
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw IoError(out_dir, "cannot create the output directory: " + ec.message());
  const DirectoryLock lock(out_dir);
  internal::writeBatchRecords(out_dir, merged);
  if (options) {
    internal::writeBatchOptions(out_dir, *options);
  } else {
    std::filesystem::remove(out_dir + "/batch.json", ec);  // not this batch's any more
  }
  writeSummary(out_dir);
}

}  // namespace skelgrasp::evaluation
