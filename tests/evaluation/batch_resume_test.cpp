// Batch evaluation's bookkeeping: failed objects, resuming, damaged records, option changes,
// merging, retries and the directory lock.
#include "skelgrasp/evaluation/batch.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "batch_test_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp::evaluation {
namespace {

using batch_test::BatchTest;
using batch_test::editLine;
using batch_test::ioErrorOf;
using batch_test::lines;
using batch_test::textOf;
using batch_test::withoutTimes;

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
      EXPECT_EQ(r["object"], "corrupt.ply");  // the folder is the list's common root
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

TEST_F(BatchTest, ARecordWithAMissingOrMistypedKeyIsAnErrorNamingFileLineAndKey) {
  const std::string out = test::tempDir("batch_damaged"), merged = test::tempDir("batch_dmerged");
  auto p = params(out);
  p.planners = {ranking::Planner::kSkeleton};
  p.max_objects = 1;
  runBatch(p);
  ASSERT_EQ(lines(out + "/runs.jsonl").size(), 1u);
  const auto kept = lines(out + "/runs.jsonl")[0]["kept"];
  ASSERT_GT(kept.get<int>(), 0);
  // A run line without "kept": before, it read as 0 and its grasps were silently dropped.
  editLine(out + "/runs.jsonl", 1, "\"kept\":" + kept.dump() + ",", "");
  p.max_objects = 0;
  const std::string expected = out + "/runs.jsonl: line 1: key 'kept' is missing";
  EXPECT_EQ(ioErrorOf([&] { runBatch(p); }), expected);  // resume
  EXPECT_EQ(ioErrorOf([&] { mergeBatches({out}, merged); }), expected);
  EXPECT_FALSE(std::filesystem::exists(merged + "/runs.jsonl")) << "nothing written";
  EXPECT_EQ(lines(out + "/runs.jsonl").size(), 1u) << "the damaged file is left as it was";
  // A key of the wrong type in results.jsonl.
  editLine(out + "/runs.jsonl", 1, "\"hand\"", "\"kept\":" + kept.dump() + ",\"hand\"");
  editLine(out + "/results.jsonl", 2, "\"epsilon\":", "\"epsilon\":\"high\",\"was\":");
  EXPECT_EQ(ioErrorOf([&] { mergeBatches({out}, merged); }),
            out + "/results.jsonl: line 2: key 'epsilon' must be a number, not \"high\"");
}

TEST_F(BatchTest, AResumeWithOtherOptionsRefusesUnlessRestarted) {
  const std::string out = test::tempDir("batch_changed_options");
  auto p = params(out);
  p.max_objects = 1;
  runBatch(p);
  const auto before = lines(out + "/runs.jsonl");
  p.max_objects = 0;
  p.quality.friction = 0.5;
  p.robustness.samples = 4;
  try {
    runBatch(p);
    FAIL() << "a resume with another mu was accepted";
  } catch (const InvalidArgument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("mu 0.35 -> 0.5"), std::string::npos) << message;
    EXPECT_NE(message.find("robustness.samples 8 -> 4"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(lines(out + "/runs.jsonl"), before);  // nothing touched
  p.restart = true;
  const auto stats = runBatch(p);
  EXPECT_EQ(stats.objects_skipped, 0u);
  EXPECT_EQ(stats.objects_run, 3u);
  const auto runs = lines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 6u);
  for (const auto& r : runs) {
    if (r["status"] != "error") {
      EXPECT_EQ(r["robustness_samples"], 4);
    }
  }
  EXPECT_EQ(readJsonFile(out + "/batch.json")["options"]["mu"], 0.5);
  p.restart = false;
  EXPECT_EQ(runBatch(p).objects_skipped, 3u);  // the new options are now the batch's
}

// A hand with alternative preshapes (the SDH's tripods) plans differently with them: batch.json
// names the hands that closed them and the preshapes, so a resume without them is refused, and
// batches of hands without any (all those from before the option) record nothing and resume as
// before.
TEST_F(BatchTest, HandsClosingAlternativePreshapesAreRecorded) {
  const std::string out = test::tempDir("batch_alternative_preshapes");
  auto p = params(out);
  p.planners = {ranking::Planner::kSkeleton};
  p.max_objects = 1;
  runBatch(p);
  EXPECT_EQ(readJsonFile(out + "/batch.json")["options"]["alternative_preshapes"],
            (nlohmann::json{{"sdh",
                             {"claw", "lateral_power", "lateral_precision",
                              "narrow_tripod (objects up to 0.07 m)", "precision_tripod"}}}));
  p.alternative_preshapes = false;
  try {
    runBatch(p);
    FAIL() << "a resume without the alternative preshapes was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("alternative_preshapes"), std::string::npos) << e.what();
  }
  const std::string armar_out = test::tempDir("batch_alternative_preshapes_armar3");
  auto armar = params(armar_out);
  armar.hands = {"armar3"};
  armar.planners = {ranking::Planner::kSkeleton};
  armar.max_objects = 1;
  runBatch(armar);
  EXPECT_FALSE(
      readJsonFile(armar_out + "/batch.json")["options"].contains("alternative_preshapes"));
  armar.alternative_preshapes = false;
  EXPECT_EQ(runBatch(armar).objects_skipped, 1u);  // the same plans: it resumes
}

TEST_F(BatchTest, MergeRefusesShardsRunWithOtherOptions) {
  const std::string s0 = test::tempDir("batch_opt_s0"), s1 = test::tempDir("batch_opt_s1"),
                    merged = test::tempDir("batch_opt_merged");
  auto p0 = params(s0);
  p0.shard_count = 2;
  p0.objects.resize(2);
  auto p1 = p0;
  p1.out_dir = s1;
  p1.shard_index = 1;
  p1.seed = 7;
  runBatch(p0);
  runBatch(p1);
  try {
    mergeBatches({s0, s1}, merged);
    FAIL() << "shards with different seeds were merged";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("seed 1 -> 7"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(merged + "/runs.jsonl"));
}

TEST_F(BatchTest, RetryFailedEvaluatesFailedObjectsAgain) {
  const std::string out = test::tempDir("batch_retry");
  const std::string broken = dir_ + "/broken.ply";
  std::ofstream(broken) << "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n";
  auto p = params(out);
  p.objects = {objects_[0], broken};
  EXPECT_EQ(runBatch(p).runs_failed, 2u);
  EXPECT_EQ(runBatch(p).objects_run, 0u);  // a failure is final without the flag
  p.retry_failed = true;
  auto stats = runBatch(p);
  EXPECT_EQ(stats.objects_run, 1u);
  EXPECT_EQ(stats.objects_retried, 1u);
  EXPECT_EQ(lines(out + "/runs.jsonl").size(), 4u);  // replaced, not added
  // The file is fixed: the retried runs succeed and replace the failed records.
  saveMesh(broken, geometry::shapes::makeNamedShape("capsule"));
  stats = runBatch(p);
  EXPECT_EQ(stats.objects_run, 1u);
  EXPECT_EQ(stats.runs_failed, 0u);
  const auto runs = lines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 4u);
  for (const auto& r : runs) EXPECT_NE(r["status"], "error") << r.dump();
  std::size_t broken_results = 0;
  for (const auto& g : lines(out + "/results.jsonl")) broken_results += g["object"] == "broken.ply";
  EXPECT_GT(broken_results, 0u);
}

TEST_F(BatchTest, AnObjectWhoseFileChangedIsEvaluatedAgain) {
  const std::string out = test::tempDir("batch_changed_file");
  auto p = params(out);
  p.objects.resize(2);
  runBatch(p);
  const auto old_hash = lines(out + "/runs.jsonl")[0]["object_hash"];
  saveMesh(objects_[0], geometry::shapes::makeNamedShape("hammer"));
  const auto stats = runBatch(p);
  EXPECT_EQ(stats.objects_run, 1u);
  EXPECT_EQ(stats.objects_changed, 1u);
  const auto runs = lines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 4u);
  for (const auto& r : runs) {
    if (r["object"] == "capsule.ply") {
      EXPECT_NE(r["object_hash"], old_hash);
    }
  }
}

TEST_F(BatchTest, ASecondWriterOfTheSameDirectoryIsRefused) {
  const std::string out = test::tempDir("batch_locked");
  // This process holds the lock as a running batch would.
  const int fd = ::open((out + "/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const std::string pid = std::to_string(::getpid());
  ASSERT_EQ(::write(fd, pid.data(), pid.size()), static_cast<ssize_t>(pid.size()));
  try {
    runBatch(params(out));
    ADD_FAILURE() << "a locked directory was written";
  } catch (const IoError& e) {
    EXPECT_EQ(e.problem(), "is in use by process " + pid);
  }
  EXPECT_FALSE(std::filesystem::exists(out + "/runs.jsonl"));
  ::close(fd);  // released: the batch runs
  EXPECT_EQ(runBatch(params(out)).objects_run, objects_.size());
}

TEST_F(BatchTest, AnObjectThatThrowsAnywhereIsRecordedAndTheRestFinish) {
  const std::string out = test::tempDir("batch_throwing_object");
  // An open surface loads, but without regularisation it has no skeleton; the surface planner
  // then has no hypothesis budget (no skeleton poses, surface_hypotheses 0, no timeout) and throws
  // InvalidArgument for this object only: the closed objects get the skeleton's pose count.
  const std::string flat = dir_ + "/flat.ply";
  std::ofstream(flat) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 1\n"
                         "property list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n0.05 0 0\n0 0.05 0\n3 0 1 2\n";
  auto p = params(out);
  p.objects = {objects_[0], flat, objects_[1]};
  p.skeleton.regularisation.method = geometry::RegularisationMethod::kNone;
  p.surface_hypotheses = 0;
  p.jobs = 2;
  const auto stats = runBatch(p);
  EXPECT_EQ(stats.objects_run, 3u);
  std::size_t ok = 0;
  for (const auto& r : lines(out + "/runs.jsonl")) {
    if (r["object"] == "flat.ply") {
      EXPECT_EQ(r["status"], "error") << r.dump();
      EXPECT_NE(r["error"].get<std::string>().find(flat), std::string::npos) << r.dump();
      if (r["planner"] == "surface") {
        EXPECT_NE(r["error"].get<std::string>().find("needs max_hypotheses"), std::string::npos)
            << r.dump();
      }
    } else {
      ok += r["status"] != "error";
    }
  }
  EXPECT_EQ(ok, 4u) << "the closed objects finish";
}

TEST_F(BatchTest, ATornLastLineFromACrashIsDroppedOnResume) {
  const std::string all = test::tempDir("batch_torn_all"), out = test::tempDir("batch_torn");
  runBatch(params(all));
  auto p = params(out);
  p.max_objects = 1;
  runBatch(p);
  // A crash while the next object was written: its results are on disk, its runs line is cut.
  std::string next_results;
  for (const auto& g : lines(all + "/results.jsonl")) {
    if (g["object"] == "hammer.ply") next_results += g.dump() + "\n";
  }
  std::ofstream(out + "/results.jsonl", std::ios::app) << next_results;
  std::ofstream(out + "/runs.jsonl", std::ios::app) << R"({"object":"hammer.ply","ha)";
  p.max_objects = 0;
  EXPECT_EQ(runBatch(p).objects_run, 2u);
  for (const char* file : {"/runs.jsonl", "/results.jsonl"}) {
    const auto a = lines(all + file), b = lines(out + file);  // parses: no torn line left
    ASSERT_EQ(a.size(), b.size()) << file;
    for (std::size_t i = 0; i < a.size(); ++i)
      EXPECT_EQ(withoutTimes(a[i]), withoutTimes(b[i])) << file << " line " << i;
  }
}

}  // namespace
}  // namespace skelgrasp::evaluation
