// The physics figures: Spearman's rank correlation against hand-computed cases, and the pooled
// figures of a small set of judged grasps.
#include <gtest/gtest.h>

#include <cmath>

#include "skelgrasp/evaluation/physics_figures.h"

namespace skelgrasp::evaluation {
namespace {

TEST(Spearman, MonotoneSeriesAreOneAndMinusOne) {
  EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4}, {10, 20, 35, 100}), 1.0);
  EXPECT_DOUBLE_EQ(spearman({1, 2, 3, 4}, {5, 4, 3, -7}), -1.0);
}

TEST(Spearman, TiesShareTheirMeanRank) {
  // x ranks 1, 2.5, 2.5, 4; y ranks 1, 2, 3, 4: Pearson of the ranks.
  const double rho = spearman({0.1, 0.5, 0.5, 0.9}, {1, 2, 3, 4});
  EXPECT_NEAR(rho, 0.9486832980505138, 1e-12);
}

TEST(Spearman, UndefinedForConstantOrShortSeries) {
  EXPECT_TRUE(std::isnan(spearman({1, 1, 1}, {1, 2, 3})));
  EXPECT_TRUE(std::isnan(spearman({1}, {2})));
  EXPECT_THROW(spearman({1, 2}, {1}), InvalidArgument);
}

TEST(PhysicsFigures, PoolsHoldsSimRAndR) {
  std::vector<JudgedGrasp> grasps(4);
  grasps[0].r = 0.9, grasps[0].sim_r = 0.8, grasps[0].nominal_holds = true;
  grasps[1].r = 0.7, grasps[1].sim_r = 0.5, grasps[1].nominal_holds = true;
  grasps[2].r = 0.5, grasps[2].sim_r = 0.2, grasps[2].nominal_holds = false;
  grasps[3].nominal_holds = false;  // not scored: no r, no sim_r
  for (auto& g : grasps) g.executions = 2, g.cpu_s = 0.1;
  const PhysicsFigures f = physicsFigures(grasps, 3, 2);
  EXPECT_EQ(f.objects, 3u);
  EXPECT_EQ(f.objects_with_grasps, 2u);
  EXPECT_EQ(f.grasps, 4u);
  EXPECT_DOUBLE_EQ(f.nominal_hold_rate, 0.5);
  ASSERT_TRUE(f.mean_sim_r && f.mean_r && f.mean_r_minus_sim_r);
  EXPECT_NEAR(*f.mean_sim_r, 0.5, 1e-12);
  EXPECT_NEAR(*f.mean_r, 0.7, 1e-12);
  EXPECT_NEAR(*f.mean_r_minus_sim_r, 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(f.spearman_r_sim_r, 1.0);
  EXPECT_NEAR(f.ms_cpu_per_execution, 50.0, 1e-9);
}

}  // namespace
}  // namespace skelgrasp::evaluation
