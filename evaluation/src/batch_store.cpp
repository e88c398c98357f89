#include "batch_store.h"

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"

namespace skelgrasp::evaluation::internal {

std::string runKey(const nlohmann::json& r) {
  return r.at("object").get<std::string>() + "|" + r.at("hand").get<std::string>() + "|" +
         r.at("planner").get<std::string>();
}

std::vector<nlohmann::json> readJsonLines(const std::string& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  if (!in) return lines;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    try {
      lines.push_back(nlohmann::json::parse(line));
    } catch (const nlohmann::json::parse_error& e) {
      throw IoError(path, "line " + std::to_string(number) + " is not JSON: " + e.what());
    }
  }
  return lines;
}

BatchStore::BatchStore(std::string dir) : dir_(std::move(dir)) {
  for (const auto& run : readJsonLines(dir_ + "/runs.jsonl")) runs_[runKey(run)] = run;
  for (const auto& result : readJsonLines(dir_ + "/results.jsonl")) {
    const std::string key = runKey(result);
    if (runs_.count(key)) results_[key].push_back(result);  // results of unfinished runs: dropped
  }
}

bool BatchStore::hasRun(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return runs_.count(key) > 0;
}

void BatchStore::add(const std::vector<nlohmann::json>& runs,
                     const std::vector<nlohmann::json>& results) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& r : runs) {
    const std::string key = runKey(r);
    runs_[key] = r;
    results_.erase(key);
  }
  for (const auto& g : results) results_[runKey(g)].push_back(g);
  write();
}

void BatchStore::write() const {
  std::string runs_text, results_text;
  for (const auto& [key, run] : runs_) runs_text += run.dump() + "\n";
  for (const auto& [key, list] : results_) {
    for (const auto& g : list) results_text += g.dump() + "\n";
  }
  // Results first: a runs.jsonl entry promises that its results are on disk.
  writeFileAtomically(dir_ + "/results.jsonl", results_text);
  writeFileAtomically(dir_ + "/runs.jsonl", runs_text);
}

}  // namespace skelgrasp::evaluation::internal
