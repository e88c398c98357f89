#pragma once
// Internal: the batch's line records (runs.jsonl, results.jsonl) kept in memory and written
// atomically, sorted so the files do not depend on evaluation order.
#include <nlohmann/json.hpp>

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace skelgrasp::evaluation::internal {

// Key of a run: object, hand, planner.
std::string runKey(const nlohmann::json& record);

class BatchStore {
 public:
  // Reads existing files of `dir` (resuming); throws IoError on malformed lines.
  explicit BatchStore(std::string dir);
  bool hasRun(const std::string& key) const;
  // Adds one object's runs and grasp results and rewrites both files.
  void add(const std::vector<nlohmann::json>& runs, const std::vector<nlohmann::json>& results);
  const std::map<std::string, nlohmann::json>& runs() const { return runs_; }
  const std::map<std::string, std::vector<nlohmann::json>>& results() const { return results_; }

 private:
  void write() const;
  std::string dir_;
  mutable std::mutex mutex_;
  std::map<std::string, nlohmann::json> runs_;
  std::map<std::string, std::vector<nlohmann::json>> results_;  // by run key
};

std::vector<nlohmann::json> readJsonLines(const std::string& path);

}  // namespace skelgrasp::evaluation::internal
