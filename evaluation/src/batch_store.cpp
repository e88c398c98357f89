#include "batch_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::evaluation::internal {
namespace {

const char* const kRunsFile = "/runs.jsonl";
const char* const kResultsFile = "/results.jsonl";

// Appends `text` (whole lines) with as few write() calls as the kernel allows: one, unless the
// disk fills up or a signal cuts it short. A cut leaves a torn last line, which readJsonLines
// drops on resume.
void appendLines(const std::string& path, const std::string& text) {
  if (text.empty()) return;
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw IoError(path, std::string("cannot open for appending: ") + std::strerror(errno));
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string problem = std::string("write failed: ") + std::strerror(errno);
      ::close(fd);
      throw IoError(path, problem);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) throw IoError(path, std::string("close failed: ") + std::strerror(errno));
}

std::string linesOf(const std::vector<nlohmann::json>& records) {
  std::string text;
  for (const auto& r : records) text += r.dump() + "\n";
  return text;
}

}  // namespace

std::string runKey(const nlohmann::json& r) {
  return r.at("object").get<std::string>() + "|" + r.at("hand").get<std::string>() + "|" +
         r.at("planner").get<std::string>();
}

std::vector<nlohmann::json> readJsonLines(const std::string& path, bool* torn_tail) {
  if (torn_tail) *torn_tail = false;
  std::vector<nlohmann::json> lines;
  std::ifstream in(path, std::ios::binary);
  if (!in) return lines;
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  std::size_t number = 0;
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    const bool last = end + 1 >= text.size();
    ++number;
    start = end + 1;
    if (line.empty()) continue;
    try {
      lines.push_back(nlohmann::json::parse(line));
    } catch (const nlohmann::json::parse_error& e) {
      // Only the last line can be cut short by a crash; anything else is real damage.
      if (!last)
        throw IoError(path, "line " + std::to_string(number) + " is not JSON: " + e.what());
      log().warn("{}: line {} is incomplete (the batch was interrupted while writing it); ignored",
                 path, number);
      if (torn_tail) *torn_tail = true;
    }
  }
  // A complete last record without its newline would have the next append glued onto it.
  if (torn_tail && !text.empty() && text.back() != '\n') *torn_tail = true;
  return lines;
}

BatchRecords loadBatchRecords(const std::string& dir) {
  BatchRecords records;
  bool torn_runs = false, torn_results = false;
  const auto runs = readJsonLines(dir + kRunsFile, &torn_runs);
  const auto results = readJsonLines(dir + kResultsFile, &torn_results);
  for (const auto& run : runs) records.runs[runKey(run)] = run;  // the last record wins
  std::map<std::string, std::vector<nlohmann::json>> all_results;
  for (const auto& result : results) all_results[runKey(result)].push_back(result);
  std::size_t kept_lines = 0;
  for (auto& [key, list] : all_results) {
    const auto run = records.runs.find(key);
    if (run == records.runs.end()) continue;  // results of an unfinished run: dropped
    const auto kept = static_cast<std::size_t>(run->second.value("kept", 0));
    if (kept == 0 || run->second.value("status", "") == "error") continue;
    if (list.size() > kept) list.erase(list.begin(), list.end() - kept);
    kept_lines += list.size();
    records.results[key] = std::move(list);
  }
  records.needs_compaction = torn_runs || torn_results || runs.size() != records.runs.size() ||
                             results.size() != kept_lines;
  return records;
}

void writeBatchRecords(const std::string& dir, const BatchRecords& records) {
  std::string runs_text, results_text;
  for (const auto& [key, run] : records.runs) runs_text += run.dump() + "\n";
  for (const auto& [key, list] : records.results) results_text += linesOf(list);
  writeFileAtomically(dir + kResultsFile, results_text);
  writeFileAtomically(dir + kRunsFile, runs_text);
}

BatchStore::BatchStore(std::string dir) : dir_(std::move(dir)), records_(loadBatchRecords(dir_)) {
  if (records_.needs_compaction) {
    log().info("{}: compacting the records of earlier attempts", dir_);
    writeBatchRecords(dir_, records_);
    records_.needs_compaction = false;
  }
}

void BatchStore::add(const std::vector<nlohmann::json>& runs,
                     const std::vector<nlohmann::json>& results) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Results first: a run line promises that its results are on disk.
  appendLines(dir_ + kResultsFile, linesOf(results));
  appendLines(dir_ + kRunsFile, linesOf(runs));
  for (const auto& r : runs) {
    const std::string key = runKey(r);
    records_.runs[key] = r;
    records_.results.erase(key);
  }
  for (const auto& g : results) records_.results[runKey(g)].push_back(g);
}

void BatchStore::compact() const {
  std::lock_guard<std::mutex> lock(mutex_);
  writeBatchRecords(dir_, records_);
}

}  // namespace skelgrasp::evaluation::internal
