#include "skelgrasp/evaluation/plan_record.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "skelgrasp/common/error.h"

namespace skelgrasp::evaluation {
namespace {

ranking::RobustRankingResult someRanking() {
  ranking::RobustRankingResult ranking;
  ranking.screened = 7;
  ranking.screen_pruned = 3;
  ranking.confirmed = 4;
  ranking.scored = 5;
  ranking.refined = 2;
  ranking.time_s = 1.0;
  ranking.screening_s = 0.25;
  ranking.scoring_s = 0.5;
  ranking.refinement_s = 0.125;
  ranking.enabled = true;
  ranking.budget = {40, 8, 0.5, grasping::ScreenCandidates::kByPreScore, 6};
  return ranking;
}

TEST(PlanRecord, RankingRecordCarriesTheCountsAndTheParts) {
  const nlohmann::json record = rankingRecordJson(someRanking());
  EXPECT_EQ(record["screened"], 7);
  EXPECT_EQ(record["screen_pruned"], 3);
  EXPECT_EQ(record["confirmed"], 4);
  EXPECT_EQ(record["scored"], 5);
  EXPECT_EQ(record["refined"], 2);
  EXPECT_DOUBLE_EQ(record["screening_s"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(record["scoring_s"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(record["refinement_s"].get<double>(), 0.125);
  EXPECT_EQ(record["budget"]["screen_grasps"], 40);
  EXPECT_EQ(record["budget"]["screen_samples"], 8);
  EXPECT_EQ(record["budget"]["screen_by"], "epsilon");
  EXPECT_EQ(record["budget"]["confirm_samples"], 6);
  EXPECT_DOUBLE_EQ(record["budget"]["refine_below_r"].get<double>(), 0.5);
}

TEST(PlanRecord, TimingSumsItsPartsAndLeavesAMissingSkeletonNull) {
  ranking::PlanTiming timing;
  timing.planning_s = 0.5;
  timing.ranking_s = 2.0;
  nlohmann::json surface = planTimingJson(timing);
  EXPECT_TRUE(surface["regularise_s"].is_null());
  EXPECT_TRUE(surface["skeleton_s"].is_null());
  EXPECT_DOUBLE_EQ(surface["total_s"].get<double>(), 2.5);

  timing.regularise_s = 0.125;
  timing.skeleton_s = 0.25;
  const nlohmann::json skeleton = planTimingJson(timing);
  EXPECT_DOUBLE_EQ(skeleton["regularise_s"].get<double>(), 0.125);
  EXPECT_DOUBLE_EQ(skeleton["skeleton_s"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(skeleton["total_s"].get<double>(), 2.875);
  EXPECT_DOUBLE_EQ(timing.total_s(), 2.875);
}

TEST(PlanRecord, TimingOfAPlanTakesTheSkeletonLessItsRegularisation) {
  skeleton::SkeletonTimings skeleton;
  skeleton.regularise_s = 0.25;
  skeleton.total_s = 0.75;  // regularisation, contraction, mapping and analysis
  const ranking::PlanTiming timing = ranking::planTimingOf(&skeleton, 1.0, 2.0);
  ASSERT_TRUE(timing.regularise_s && timing.skeleton_s);
  EXPECT_DOUBLE_EQ(*timing.regularise_s, 0.25);
  EXPECT_DOUBLE_EQ(*timing.skeleton_s, 0.5);
  EXPECT_DOUBLE_EQ(timing.total_s(), 3.75);
  const ranking::PlanTiming surface = ranking::planTimingOf(nullptr, 1.0, 2.0);
  EXPECT_FALSE(surface.regularise_s || surface.skeleton_s);
  EXPECT_DOUBLE_EQ(surface.total_s(), 3.0);
}

TEST(PlanRecord, DisabledRankingIsNullAndTheDocumentKeepsItsMembers) {
  nlohmann::json document = {{"schema", "skelgrasp.grasps/3"}, {"grasps", nlohmann::json::array()}};
  ranking::PlanTiming timing;
  timing.planning_s = 0.5;
  ranking::RobustRankingResult disabled = someRanking();
  disabled.enabled = false;
  addPlanRecords(document, disabled, timing);
  EXPECT_TRUE(document["ranking"].is_null());
  EXPECT_DOUBLE_EQ(document["timing"]["planning_s"].get<double>(), 0.5);
  EXPECT_EQ(document["schema"], "skelgrasp.grasps/3");

  addPlanRecords(document, someRanking(), timing);
  EXPECT_EQ(document["ranking"]["scored"], 5);
}

TEST(PlanRecord, RejectsTimesThatAreNoTimesAndDocumentsThatAreNoObjects) {
  ranking::PlanTiming negative;
  negative.ranking_s = -1e-3;
  EXPECT_THROW(planTimingJson(negative), InvalidArgument);
  ranking::PlanTiming not_a_number;
  not_a_number.regularise_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(planTimingJson(not_a_number), InvalidArgument);
  nlohmann::json list = nlohmann::json::array();
  EXPECT_THROW(addPlanRecords(list, someRanking(), ranking::PlanTiming{}), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::evaluation
