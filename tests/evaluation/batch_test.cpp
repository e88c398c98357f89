// Batch evaluation: shards, failures, resuming, summary files.
#include "skelgrasp/evaluation/batch.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/primitives.h"
#include "test_support.h"

namespace skelgrasp::evaluation {
namespace {

std::vector<nlohmann::json> lines(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  }
  return out;
}

// Everything except wall-clock times, which differ between runs by nature.
nlohmann::json withoutTimes(nlohmann::json j) {
  for (const char* key : {"planning_s", "regularise_s", "skeleton_s", "robustness_s",
                          "ms_per_valid_grasp", "time_ms", "timed_out"}) {
    j.erase(key);
  }
  return j;
}

class BatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::tempDir("batch_objects");
    for (const char* shape : {"capsule", "bottle", "hammer"}) {
      objects_.push_back(dir_ + "/" + shape + ".ply");
      saveMesh(objects_.back(), primitives::makeNamedShape(shape));
    }
  }
  BatchParams params(const std::string& out) const {
    BatchParams p;
    p.objects = objects_;
    p.hands = {"sdh"};
    p.out_dir = out;
    p.timeout_s = 0;  // results must not depend on machine speed here
    p.vertex_distance_m = 0.01;
    p.surface_hypotheses = 40;
    p.robustness_grasps = 2;
    p.robustness.samples = 8;
    return p;
  }
  std::string dir_;
  std::vector<std::string> objects_;
};

TEST_F(BatchTest, ShardsTogetherGiveExactlyTheUnshardedResults) {
  const std::string all = test::tempDir("batch_all"), s0 = test::tempDir("batch_s0"),
                    s1 = test::tempDir("batch_s1"), merged = test::tempDir("batch_merged");
  runBatch(params(all));
  auto p0 = params(s0);
  p0.shard_index = 0;
  p0.shard_count = 2;
  auto p1 = params(s1);
  p1.shard_index = 1;
  p1.shard_count = 2;
  p1.jobs = 2;
  const auto stats0 = runBatch(p0), stats1 = runBatch(p1);
  EXPECT_EQ(stats0.objects_total + stats1.objects_total, objects_.size());
  mergeBatches({s0, s1}, merged);
  for (const char* file : {"/runs.jsonl", "/results.jsonl"}) {
    const auto a = lines(all + file), b = lines(merged + file);
    ASSERT_EQ(a.size(), b.size()) << file;
    for (std::size_t i = 0; i < a.size(); ++i)
      EXPECT_EQ(withoutTimes(a[i]), withoutTimes(b[i])) << file << " line " << i;
  }
  // Six runs (3 objects x 1 hand x 2 planners), summary files and the hand's histogram.
  EXPECT_EQ(lines(all + "/runs.jsonl").size(), 6u);
  for (const char* file : {"/summary.md", "/summary.csv", "/robustness_sdh.png"}) {
    EXPECT_TRUE(std::filesystem::exists(merged + file)) << file;
  }
  std::ifstream csv(merged + "/summary.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(
      header,
      "hand,planner,objects,grasps,ms_per_valid_grasp,ms_per_valid_grasp_std,force_closure_rate,"
      "force_closure_rate_std,robustness,robustness_std,precision,power");
}

TEST_F(BatchTest, ACorruptObjectIsReportedAndTheRestFinish) {
  const std::string out = test::tempDir("batch_corrupt");
  auto p = params(out);
  std::ofstream(dir_ + "/corrupt.ply")
      << "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n";
  p.objects.insert(p.objects.begin() + 1, dir_ + "/corrupt.ply");
  const auto stats = runBatch(p);
  EXPECT_EQ(stats.runs_failed, 2u);  // its skeleton and surface runs
  std::size_t errors = 0, finished = 0;
  for (const auto& r : lines(out + "/runs.jsonl")) {
    if (r["status"] == "error") {
      ++errors;
      EXPECT_EQ(r["object"], "corrupt.ply");
      EXPECT_NE(r["error"].get<std::string>().find("corrupt.ply"), std::string::npos);
    } else {
      ++finished;
    }
  }
  EXPECT_EQ(errors, 2u);
  EXPECT_EQ(finished, 6u);
}

TEST_F(BatchTest, AnInterruptedRunResumesWithoutRedoingFinishedWork) {
  const std::string out = test::tempDir("batch_resume");
  auto p = params(out);
  p.max_objects = 1;  // "interrupted" after the first object
  EXPECT_EQ(runBatch(p).objects_run, 1u);
  const auto first = lines(out + "/runs.jsonl");
  ASSERT_EQ(first.size(), 2u);
  p.max_objects = 0;
  const auto stats = runBatch(p);
  EXPECT_EQ(stats.objects_skipped, 1u);
  EXPECT_EQ(stats.objects_run, 2u);
  const auto all = lines(out + "/runs.jsonl");
  EXPECT_EQ(all.size(), 6u);
  // The finished runs were kept as they were (same timings: not recomputed).
  for (const auto& r : first) {
    bool found = false;
    for (const auto& a : all) found = found || a == r;
    EXPECT_TRUE(found) << r.dump();
  }
  EXPECT_EQ(runBatch(p).objects_run, 0u);  // nothing left to do
}

TEST_F(BatchTest, RejectsBadParameters) {
  auto p = params(test::tempDir("batch_bad"));
  p.shard_index = 2;
  p.shard_count = 2;
  EXPECT_THROW(runBatch(p), InvalidArgument);
  p = params(test::tempDir("batch_bad"));
  p.planners = {"random"};
  EXPECT_THROW(runBatch(p), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::evaluation
