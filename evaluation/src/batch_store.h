#pragma once
// Internal: the batch's line records (runs.jsonl, results.jsonl). While a batch runs, every
// object's records are appended as whole lines (one write per file), so an interrupted batch
// loses at most the object in flight; the files are compacted (one line per run, sorted) when the
// batch ends or resumes. docs/evaluation.md describes the files.
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "batch_records.h"

namespace skelgrasp::evaluation::internal {

// The records of runs.jsonl or results.jsonl at `path` (none when it does not exist). A last line
// cut short by a crash is dropped with a warning (*torn_tail set when given); a line elsewhere that
// is not JSON, or any line with a key missing or of the wrong type, throws IoError naming the line
// and the key.
std::vector<RunRecord> readRunRecords(const std::string& path, bool* torn_tail = nullptr);
std::vector<GraspRecord> readGraspRecords(const std::string& path, bool* torn_tail = nullptr);

// The runs of a batch directory and the grasp results of each run. A run recorded more than once
// (an interrupted or retried attempt) keeps its last record, and its results are its last `kept`
// result lines (results are appended before the run line that promises them).
struct BatchRecords {
  std::map<std::string, RunRecord> runs;                    // by run key
  std::map<std::string, std::vector<GraspRecord>> results;  // by run key
  bool needs_compaction = false;  // superseded, orphaned or torn lines on disk
};
// Throws IoError for a damaged line (see readRunRecords).
BatchRecords loadBatchRecords(const std::string& dir);

// Writes `records` as compact, sorted runs.jsonl and results.jsonl (each atomically; results first:
// a run line promises that its results are on disk).
void writeBatchRecords(const std::string& dir, const BatchRecords& records);

class BatchStore {
 public:
  // Reads the records of `dir` (resuming) and compacts the files when needed.
  explicit BatchStore(std::string dir);
  // Appends one object's grasp results, then its runs; safe to call from several threads.
  void add(const std::vector<RunRecord>& runs, const std::vector<GraspRecord>& results);
  // Rewrites the files compacted and sorted, so they do not depend on evaluation order.
  void compact() const;
  // Only while no add() runs concurrently (before the batch's objects are started).
  const BatchRecords& records() const { return records_; }

 private:
  std::string dir_;
  mutable std::mutex mutex_;
  BatchRecords records_;
};

}  // namespace skelgrasp::evaluation::internal
