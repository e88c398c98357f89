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

template <typename Record>
std::string linesOf(const std::vector<Record>& records) {
  std::string text;
  for (const auto& r : records) text += nlohmann::json(r).dump() + "\n";
  return text;
}

// The JSON lines of `path` converted to Records; see readRunRecords.
template <typename Record>
std::vector<Record> readRecords(const std::string& path, bool* torn_tail) {
  if (torn_tail) *torn_tail = false;
  std::vector<Record> records;
  std::ifstream in(path, std::ios::binary);
  if (!in) return records;
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  std::size_t number = 0;
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    const bool last = end + 1 >= text.size();
    ++number;
    start = end + 1;
    if (line.empty()) continue;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::parse_error& e) {
      // Only the last line can be cut short by a crash; anything else is real damage.
      if (!last)
        throw IoError(path, "line " + std::to_string(number) + " is not JSON: " + e.what());
      log().warn("{}: line {} is incomplete (the batch was interrupted while writing it); ignored",
                 path, number);
      if (torn_tail) *torn_tail = true;
      continue;
    }
    try {
      records.push_back(j.get<Record>());
    } catch (const RecordError& e) {
      throw IoError(path, "line " + std::to_string(number) + ": " + e.what());
    }
  }
  // A complete last record without its newline would have the next append glued onto it.
  if (torn_tail && !text.empty() && text.back() != '\n') *torn_tail = true;
  return records;
}

}  // namespace

std::vector<RunRecord> readRunRecords(const std::string& path, bool* torn_tail) {
  return readRecords<RunRecord>(path, torn_tail);
}

std::vector<GraspRecord> readGraspRecords(const std::string& path, bool* torn_tail) {
  return readRecords<GraspRecord>(path, torn_tail);
}

BatchRecords loadBatchRecords(const std::string& dir) {
  BatchRecords records;
  bool torn_runs = false, torn_results = false;
  auto runs = readRunRecords(dir + kRunsFile, &torn_runs);
  auto results = readGraspRecords(dir + kResultsFile, &torn_results);
  const std::size_t run_lines = runs.size(), result_lines = results.size();
  for (auto& run : runs) records.runs[runKey(run)] = std::move(run);  // the last record wins
  std::map<std::string, std::vector<GraspRecord>> all_results;
  for (auto& result : results) all_results[runKey(result)].push_back(std::move(result));
  std::size_t kept_lines = 0;
  for (auto& [key, list] : all_results) {
    const auto run = records.runs.find(key);
    if (run == records.runs.end()) continue;      // results of an unfinished run: dropped
    const auto& measures = run->second.measures;  // none for a failed run: no results
    const std::size_t kept = measures ? measures->kept : 0;
    if (kept == 0) continue;
    if (list.size() > kept) list.erase(list.begin(), list.end() - kept);
    kept_lines += list.size();
    records.results[key] = std::move(list);
  }
  records.needs_compaction =
      torn_runs || torn_results || run_lines != records.runs.size() || result_lines != kept_lines;
  return records;
}

void writeBatchRecords(const std::string& dir, const BatchRecords& records) {
  std::string runs_text, results_text;
  for (const auto& [key, run] : records.runs) runs_text += nlohmann::json(run).dump() + "\n";
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

void BatchStore::add(const std::vector<RunRecord>& runs, const std::vector<GraspRecord>& results) {
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
