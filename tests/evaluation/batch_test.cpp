// Batch evaluation: shards, failures, resuming, summary files.
#include "skelgrasp/evaluation/batch.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

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

std::string textOf(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Everything except wall-clock times, which differ between runs by nature.
nlohmann::json withoutTimes(nlohmann::json j) {
  for (const char* key : {"planning_s", "regularise_s", "skeleton_s", "robustness_s",
                          "ms_per_valid_grasp", "time_ms", "timed_out", "ranking_s"}) {
    j.erase(key);
  }
  return j;
}

class BatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Per test: ctest runs the tests of this fixture in parallel processes.
    dir_ = test::tempDir(std::string("batch_objects_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
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

TEST_F(BatchTest, RejectsBadParameters) {
  auto p = params(test::tempDir("batch_bad"));
  p.shard_index = 2;
  p.shard_count = 2;
  EXPECT_THROW(runBatch(p), InvalidArgument);
}

TEST(PlannerTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const Planner planner : {Planner::kSkeleton, Planner::kSurface})
    EXPECT_EQ(parsePlanner(toString(planner)), planner);
  EXPECT_STREQ(toString(Planner::kSkeleton), "skeleton");
  EXPECT_STREQ(toString(Planner::kSurface), "surface");
  try {
    parsePlanner("random");
    FAIL() << "an unknown planner was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_STREQ(e.what(), "unknown planner 'random' (use skeleton, surface)");
  }
}

// Replaces the text `from` by `to` in line `line` (1-based) of `path`.
void editLine(const std::string& path, std::size_t line, const std::string& from,
              const std::string& to) {
  std::vector<std::string> text;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) text.push_back(l);
  }
  ASSERT_GE(text.size(), line) << path;
  const auto at = text[line - 1].find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in line " << line << " of " << path;
  text[line - 1].replace(at, from.size(), to);
  std::ofstream out(path, std::ios::trunc);
  for (const auto& l : text) out << l << "\n";
}

// The IoError message of `action`, or a failure when it does not throw one.
template <typename Action>
std::string ioErrorOf(Action action) {
  try {
    action();
  } catch (const IoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no IoError";
  return "";
}

TEST_F(BatchTest, ARecordWithAMissingOrMistypedKeyIsAnErrorNamingFileLineAndKey) {
  const std::string out = test::tempDir("batch_damaged"), merged = test::tempDir("batch_dmerged");
  auto p = params(out);
  p.planners = {Planner::kSkeleton};
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

TEST_F(BatchTest, SameNamedMeshesInDifferentFoldersAreDistinctRunsWithDistinctSeeds) {
  const std::string objects = test::tempDir("batch_same_names"), out = objects + "/out";
  std::filesystem::create_directories(objects + "/a");
  std::filesystem::create_directories(objects + "/b");
  saveMesh(objects + "/a/mesh.ply", primitives::makeNamedShape("capsule"));
  saveMesh(objects + "/b/mesh.ply", primitives::makeNamedShape("bottle"));
  auto p = params(out);
  p.objects = {objects + "/a/mesh.ply", objects + "/b/mesh.ply"};
  EXPECT_EQ(runBatch(p).objects_run, 2u);
  const auto runs = lines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 4u);  // 2 objects x 1 hand x 2 planners: nothing overwritten
  std::map<std::string, std::set<std::uint64_t>> seeds;  // by planner
  std::set<std::string> ids, hashes;
  for (const auto& r : runs) {
    ids.insert(r["object"].get<std::string>());
    hashes.insert(r["object_hash"].get<std::string>());
    seeds[r["planner"].get<std::string>()].insert(r["seed"].get<std::uint64_t>());
  }
  EXPECT_EQ(ids, (std::set<std::string>{"a/mesh.ply", "b/mesh.ply"}));
  EXPECT_EQ(hashes.size(), 2u);
  for (const auto& [planner, set] : seeds) EXPECT_EQ(set.size(), 2u) << planner;
  std::set<std::string> result_ids;
  for (const auto& g : lines(out + "/results.jsonl")) result_ids.insert(g["object"]);
  EXPECT_EQ(result_ids, ids);  // both objects kept their grasps
  // The same list again: both are recognised as done.
  EXPECT_EQ(runBatch(p).objects_skipped, 2u);
}

// The surface planner's budget is the skeleton planner's pose count whichever planner is named
// first, so both orders give the same runs and grasps per planner.
TEST_F(BatchTest, ThePlannersOrderDoesNotChangeTheirResults) {
  const auto byPlanner = [](const std::string& path) {
    std::map<std::string, std::vector<nlohmann::json>> out;
    for (const auto& r : lines(path))
      out[r["planner"].get<std::string>()].push_back(withoutTimes(r));
    return out;
  };
  const std::string forward = test::tempDir("batch_order_ab"),
                    backward = test::tempDir("batch_order_ba");
  auto p = params(forward);
  p.objects = {objects_.front()};
  p.planners = {Planner::kSkeleton, Planner::kSurface};
  runBatch(p);
  p.out_dir = backward;
  p.planners = {Planner::kSurface, Planner::kSkeleton};
  runBatch(p);
  const auto runs = byPlanner(forward + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_GT(runs.at("surface").front()["hypotheses"].get<std::size_t>(), 0u);
  EXPECT_EQ(runs.at("surface").front()["hypotheses"], runs.at("skeleton").front()["poses"]);
  EXPECT_EQ(byPlanner(backward + "/runs.jsonl"), runs);
  EXPECT_EQ(byPlanner(backward + "/results.jsonl"), byPlanner(forward + "/results.jsonl"));
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

TEST_F(BatchTest, RobustRankingRecordsTheReturnedGraspsRAndIsPartOfTheOptions) {
  const std::string out = test::tempDir("batch_ranking");
  auto p = params(out);
  p.planners = {Planner::kSkeleton};
  p.ranking.enabled = true;
  p.ranking.top_k = 2;
  p.ranking.screen_k = 4;
  p.ranking.screen_samples = 4;
  p.ranking.robustness.samples = 6;
  runBatch(p);
  const auto runs = lines(out + "/runs.jsonl");
  ASSERT_EQ(runs.size(), objects_.size());
  std::size_t ranked_with_grasps = 0;
  for (const auto& run : runs) {
    ASSERT_EQ(run["status"] != "error", true) << run.dump();
    EXPECT_TRUE(run["ranked"].get<bool>());
    const std::size_t kept = run["kept"];
    EXPECT_EQ(run["ranked_grasps"].get<std::size_t>(), std::min<std::size_t>(kept, 2));
    if (kept == 0) {
      EXPECT_TRUE(run["ranked_r_mean"].is_null());
      continue;
    }
    ++ranked_with_grasps;
    const double r = run["ranked_r_mean"];
    EXPECT_GE(r, 0.0);
    EXPECT_LE(r, 1.0);
    // The scored grasps' samples: each failed one has one cause, the rest held (r's mean).
    const std::size_t samples = run["ranked_samples"];
    EXPECT_EQ(samples, run["ranked_grasps"].get<std::size_t>() * 6);
    const auto& failures = run["ranked_failures"];
    const std::size_t failed = failures["start_collision"].get<std::size_t>() +
                               failures["closing"].get<std::size_t>() +
                               failures["no_force_closure"].get<std::size_t>();
    EXPECT_EQ(samples - failed, static_cast<std::size_t>(std::lround(r * samples)));
  }
  EXPECT_GT(ranked_with_grasps, 0u);
  // The summary shows the returned grasps' table; the options record the ranking, so a resume
  // without it is refused.
  const std::string summary = textOf(out + "/summary.md");
  EXPECT_NE(summary.find("## Returned grasps (robust ranking)"), std::string::npos);
  EXPECT_NE(summary.find("| start in object | too few contacts | slipped |"), std::string::npos);
  EXPECT_EQ(readJsonFile(out + "/batch.json")["options"]["ranking"]["top_k"], 2);
  // The search for more robust poses moves the returned grasps: another search is another batch.
  auto other_search = p;
  other_search.ranking.refinement.max_standoff_m += 0.01;
  EXPECT_THROW(runBatch(other_search), InvalidArgument);
  p.ranking.enabled = false;
  EXPECT_THROW(runBatch(p), InvalidArgument);
  // A batch without ranking records no ranking options and no such table.
  const std::string plain = test::tempDir("batch_no_ranking");
  auto q = params(plain);
  q.planners = {Planner::kSkeleton};
  q.max_objects = 1;
  runBatch(q);
  EXPECT_FALSE(readJsonFile(plain + "/batch.json")["options"].contains("ranking"));
  EXPECT_EQ(textOf(plain + "/summary.md").find("Returned grasps"), std::string::npos);
  for (const auto& run : lines(plain + "/runs.jsonl")) EXPECT_FALSE(run["ranked"].get<bool>());
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
  saveMesh(broken, primitives::makeNamedShape("capsule"));
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
  saveMesh(objects_[0], primitives::makeNamedShape("hammer"));
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
