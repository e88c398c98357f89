#pragma once
// Internal: what identifies a batch (the options that shape its results, stored in batch.json)
// and its objects (an id unique within the list plus a hash of the file's bytes).
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/evaluation/batch.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::evaluation::internal {

// Version of batch.json and of the run records' layout (docs/evaluation.md).
constexpr int kBatchSchemaVersion = 1;

// Every option of `params` that changes a run's records; not jobs, shards, out_dir or the list.
// `hands` are params.hands resolved: which of them close alternative preshapes is recorded.
nlohmann::json resultOptions(const BatchParams& params,
                             const std::vector<grasping::HandModel>& hands);

// "mu 0.35 -> 0.5, robustness.samples 8 -> 4" for the options that differ; empty when none.
std::string describeDifferences(const nlohmann::json& recorded, const nlohmann::json& current);

// The "options" of DIR/batch.json; nullopt when the directory has none (older skelgrasp).
// Throws IoError for a malformed file or a newer schema.
std::optional<nlohmann::json> readBatchOptions(const std::string& dir);
void writeBatchOptions(const std::string& dir, const nlohmann::json& options);

// Stable across builds and platforms (std::hash is not): 64-bit FNV-1a.
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t seed = 0);

struct ObjectIdentity {
  std::string path;  // as given
  // The path relative to the deepest directory holding every object of the list, '/'-separated:
  // unique within the list, the same for every shard, the bare file name for a flat folder.
  std::string id;
  std::string hash;  // FNV-1a of the file's bytes, 16 hex digits; empty when unreadable
};

// Identities of `paths` in order. A path listed twice (after normalisation) is kept once, with a
// warning. Hashes are left empty: contentHash reads the file, so only a shard's objects get one.
std::vector<ObjectIdentity> identifyObjects(const std::vector<std::string>& paths);
// FNV-1a of the file's bytes as 16 hex digits; empty when it cannot be read.
std::string contentHash(const std::string& path);

}  // namespace skelgrasp::evaluation::internal
