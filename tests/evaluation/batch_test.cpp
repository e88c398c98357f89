// Batch evaluation: shards, planners, robust ranking, parameters.
#include "skelgrasp/evaluation/batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "batch_test_support.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp::evaluation {
namespace {

using batch_test::BatchTest;
using batch_test::lines;
using batch_test::textOf;
using batch_test::withoutTimes;

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

TEST_F(BatchTest, RejectsBadParameters) {
  const std::string dir = test::tempDir("batch_bad");
  auto p = params(dir);
  p.shard_index = 2;
  p.shard_count = 2;
  EXPECT_THROW(runBatch(p), InvalidArgument);
  // The ranking's own mistakes are refused before any work starts, as the ranking refuses them
  // (ranking::checkRobustRankingParams): nothing is written.
  const auto bad_rankings = {
      +[](ranking::RobustRankingParams& r) { r.confirm_samples = -1; },
      +[](ranking::RobustRankingParams& r) { r.screen_samples = 0; },
      +[](ranking::RobustRankingParams& r) { r.robustness.samples = 0; },
      +[](ranking::RobustRankingParams& r) { r.refinement.search_below_r = 1.5; },
      +[](ranking::RobustRankingParams& r) { r.friction = -0.1; },
  };
  for (const auto spoil : bad_rankings) {
    auto q = params(dir);
    q.ranking.enabled = true;
    spoil(q.ranking);
    EXPECT_THROW(runBatch(q), InvalidArgument);
    EXPECT_FALSE(std::filesystem::exists(dir + "/batch.json"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/runs.jsonl"));
  }
}

TEST(PlannerTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const ranking::Planner planner : {ranking::Planner::kSkeleton, ranking::Planner::kSurface})
    EXPECT_EQ(ranking::parsePlanner(toString(planner)), planner);
  EXPECT_STREQ(toString(ranking::Planner::kSkeleton), "skeleton");
  EXPECT_STREQ(toString(ranking::Planner::kSurface), "surface");
  try {
    ranking::parsePlanner("random");
    FAIL() << "an unknown planner was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_STREQ(e.what(), "unknown planner 'random' (use skeleton, surface)");
  }
}

TEST_F(BatchTest, SameNamedMeshesInDifferentFoldersAreDistinctRunsWithDistinctSeeds) {
  const std::string objects = test::tempDir("batch_same_names"), out = objects + "/out";
  std::filesystem::create_directories(objects + "/a");
  std::filesystem::create_directories(objects + "/b");
  saveMesh(objects + "/a/mesh.ply", geometry::shapes::makeNamedShape("capsule"));
  saveMesh(objects + "/b/mesh.ply", geometry::shapes::makeNamedShape("bottle"));
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
  p.planners = {ranking::Planner::kSkeleton, ranking::Planner::kSurface};
  runBatch(p);
  p.out_dir = backward;
  p.planners = {ranking::Planner::kSurface, ranking::Planner::kSkeleton};
  runBatch(p);
  const auto runs = byPlanner(forward + "/runs.jsonl");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_GT(runs.at("surface").front()["hypotheses"].get<std::size_t>(), 0u);
  EXPECT_EQ(runs.at("surface").front()["hypotheses"], runs.at("skeleton").front()["poses"]);
  EXPECT_EQ(byPlanner(backward + "/runs.jsonl"), runs);
  EXPECT_EQ(byPlanner(backward + "/results.jsonl"), byPlanner(forward + "/results.jsonl"));
}

TEST_F(BatchTest, RobustRankingRecordsTheReturnedGraspsRAndIsPartOfTheOptions) {
  const std::string out = test::tempDir("batch_ranking");
  auto p = rankedParams(out, 2, 4);
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
    const std::size_t failed =
        failures["start_collision"].get<std::size_t>() + failures["closing"].get<std::size_t>() +
        failures["no_force_closure"].get<std::size_t>() + failures["too_weak"].get<std::size_t>();
    EXPECT_EQ(samples - failed, static_cast<std::size_t>(std::lround(r * samples)));
  }
  EXPECT_GT(ranked_with_grasps, 0u);
  // The summary shows the returned grasps' table; the options record the ranking, so a resume
  // without it is refused.
  const std::string summary = textOf(out + "/summary.md");
  EXPECT_NE(summary.find("## Returned grasps (robust ranking)"), std::string::npos);
  EXPECT_NE(summary.find("| start in object | too few contacts | slipped |"), std::string::npos);
  // It names what r depends on: friction, contact model, how r was sampled and ranked.
  EXPECT_NE(summary.find("Settings (batch.json): μ = 0.35; each hand's own contact model"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("robust ranking: 4 screened (each preshape's best in turn) with 4 "
                         "samples, the best 4 of them confirmed with 10 more, the best 2 scored "
                         "with 6"),
            std::string::npos)
      << summary;
  EXPECT_EQ(readJsonFile(out + "/batch.json")["options"]["ranking"]["top_k"], 2);
  // How a found pose was checked is part of what r means: a batch from before the check on its
  // own samples (no "check") does not resume into this one.
  const nlohmann::json batch_json = readJsonFile(out + "/batch.json");
  EXPECT_EQ(batch_json["options"]["ranking"]["refinement"]["check"], "own_samples");
  nlohmann::json before_check = batch_json;
  before_check["options"]["ranking"]["refinement"].erase("check");
  std::ofstream(out + "/batch.json") << before_check.dump(2);
  EXPECT_THROW(runBatch(p), InvalidArgument);
  std::ofstream(out + "/batch.json") << batch_json.dump(2);
  // The search for more robust poses moves the returned grasps: another search is another batch.
  auto other_search = p;
  other_search.ranking.refinement.max_standoff_m += 0.01;
  EXPECT_THROW(runBatch(other_search), InvalidArgument);
  p.ranking.enabled = false;
  EXPECT_THROW(runBatch(p), InvalidArgument);
  // A batch without ranking records no ranking options and no such table.
  const std::string plain = test::tempDir("batch_no_ranking");
  auto q = params(plain);
  q.planners = {ranking::Planner::kSkeleton};
  q.max_objects = 1;
  runBatch(q);
  EXPECT_FALSE(readJsonFile(plain + "/batch.json")["options"].contains("ranking"));
  EXPECT_EQ(textOf(plain + "/summary.md").find("Returned grasps"), std::string::npos);
  EXPECT_EQ(textOf(plain + "/summary.md").find("robust ranking:"), std::string::npos);
  // Soft-finger contacts are named with their torsion.
  const std::string soft = test::tempDir("batch_soft");
  auto s = params(soft);
  s.planners = {ranking::Planner::kSkeleton};
  s.max_objects = 1;
  s.quality.torsional_friction_m = 0.0023;
  runBatch(s);
  EXPECT_NE(textOf(soft + "/summary.md").find("soft-finger contacts (torsional friction 2.3 mm)"),
            std::string::npos);
  for (const auto& run : lines(plain + "/runs.jsonl")) EXPECT_FALSE(run["ranked"].get<bool>());
}

TEST_F(BatchTest, TheRefinementsShareIsWhatTheSameBatchReturnsWithoutIt) {
  // The refinement for robustness runs after the scoring and moves only the grasps it searches:
  // the scored grasps' r before it, recorded per run, is the r of the same batch without it.
  const std::string refined = test::tempDir("batch_refined"),
                    unrefined = test::tempDir("batch_unrefined");
  auto p = rankedParams(refined, 4, 8);
  // The ranking's own bar, not the SDH's lower one: with the few grasps of this batch the
  // refinement then moves some.
  p.ranking.refinement.search_below_r = ranking::kDefaultSearchBelowR;
  runBatch(p);
  auto q = p;
  q.out_dir = unrefined;
  q.ranking.refinement.enabled = false;
  runBatch(q);
  const auto with = lines(refined + "/runs.jsonl"), without = lines(unrefined + "/runs.jsonl");
  ASSERT_EQ(with.size(), without.size());
  std::size_t moved = 0, compared = 0;
  for (std::size_t i = 0; i < with.size(); ++i) {
    ASSERT_EQ(with[i]["object"], without[i]["object"]);
    moved += with[i]["ranked_refined"].get<std::size_t>();
    EXPECT_EQ(without[i]["ranked_refined"].get<std::size_t>(), 0u);
    EXPECT_EQ(without[i]["ranked_r_mean_unrefined"], without[i]["ranked_r_mean"]);
    if (with[i]["ranked_r_mean"].is_null()) {
      EXPECT_TRUE(with[i]["ranked_r_mean_unrefined"].is_null());
      continue;
    }
    ++compared;
    EXPECT_DOUBLE_EQ(with[i]["ranked_r_mean_unrefined"].get<double>(),
                     without[i]["ranked_r_mean"].get<double>())
        << with[i]["object"];
    EXPECT_GE(with[i]["ranked_refinement_s"].get<double>(), 0.0);
    EXPECT_LE(with[i]["ranked_refinement_s"].get<double>(), with[i]["ranking_s"].get<double>());
  }
  EXPECT_GT(compared, 0u);
  EXPECT_GT(moved, 0u) << "no grasp was moved: the comparison shows nothing";
  const std::string header = "| hand | planner | grasps moved | top r without | top r with |";
  EXPECT_NE(textOf(refined + "/summary.md").find(header), std::string::npos);
  // Records from before the share was recorded: the summary leaves the table out rather than
  // count those runs as unrefined.
  std::vector<nlohmann::json> old_records = with;
  {
    std::ofstream out(refined + "/runs.jsonl", std::ios::trunc);
    for (auto& run : old_records) {
      run.erase("ranked_r_mean_unrefined");
      run.erase("ranked_refinement_s");
      out << run.dump() << "\n";
    }
  }
  writeSummary(refined);
  EXPECT_EQ(textOf(refined + "/summary.md").find(header), std::string::npos);
  EXPECT_NE(textOf(refined + "/summary.md").find("## Returned grasps (robust ranking)"),
            std::string::npos);
}

}  // namespace
}  // namespace skelgrasp::evaluation
