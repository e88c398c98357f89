// Memory estimates of the scene occupancy octree and the 6D wrench hull (docs/limits.md).
#include <gtest/gtest.h>

#include <random>

#include "perception/synthetic_scenes.h"
#include "skelgrasp/common/resources.h"
#include "skelgrasp/grasping/planning/scene.h"
#include "skelgrasp/grasping/quality/quality.h"

namespace skelgrasp::grasping {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

TEST(SceneOccupancyEstimate, GrowsAsTheResolutionShrinks) {
  const auto scene = test::renderTableScene(41);
  SceneOccupancyParams params;
  double previous = 0;
  for (double resolution : {0.02, 0.01, 0.005, 0.0025, 0.001, 1e-6}) {
    params.resolution_m = resolution;
    const double bytes =
        estimateSceneOccupancyBytes(scene.cloud, scene.cloud.sensor_origin, params);
    EXPECT_GT(bytes, previous) << resolution;
    previous = bytes;
  }
  EXPECT_GT(previous, 100 * kGiB);  // 1 micrometre cells
}

TEST(SceneOccupancyEstimate, DefaultsAreFarBelowTheLimitAndTinyCellsRefuse) {
  const auto scene = test::renderTableScene(41);
  EXPECT_LT(estimateSceneOccupancyBytes(scene.cloud, scene.cloud.sensor_origin), 0.5 * kGiB);
  SceneOccupancyParams cautious;
  cautious.unknown = UnknownSpace::kOccupied;
  EXPECT_LT(estimateSceneOccupancyBytes(scene.cloud, scene.cloud.sensor_origin, cautious),
            2 * kGiB);
  SceneOccupancyParams tiny;
  tiny.resolution_m = 1e-6;
  EXPECT_THROW(SceneOccupancy(scene.cloud, scene.cloud.sensor_origin, tiny), ResourceLimitExceeded);
}

std::vector<Contact> sphereContacts(int count) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  std::vector<Contact> contacts;
  for (int i = 0; i < count; ++i) {
    Contact c;
    c.normal = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    c.point = 0.05 * c.normal;
    contacts.push_back(c);
  }
  return contacts;
}

TEST(WrenchHullEstimate, CountsWrenchesAndGrowsWithThem) {
  QualityParams params;
  EXPECT_EQ(wrenchCount(4, params), 32u);
  params.torsional_friction_m = 0.01;
  EXPECT_EQ(wrenchCount(4, params), 64u);
  double previous = 0;
  for (std::size_t wrenches : {32, 80, 320, 1280, 16000}) {
    const double bytes = estimateWrenchHullBytes(wrenches);
    EXPECT_GT(bytes, previous) << wrenches;
    previous = bytes;
  }
  // A five-finger grasp is nothing; two thousand contacts are.
  EXPECT_LT(estimateWrenchHullBytes(wrenchCount(5, QualityParams{})), 0.01 * kGiB);
  EXPECT_GT(estimateWrenchHullBytes(wrenchCount(2000, QualityParams{})), 8 * kGiB);
}

TEST(WrenchHullEstimate, EvaluationRefusesGiantContactSetsOnly) {
  EXPECT_TRUE(evaluateWrenchSpace(sphereContacts(6), Eigen::Vector3d::Zero(), 20).force_closure);
  EXPECT_THROW(evaluateWrenchSpace(sphereContacts(2000), Eigen::Vector3d::Zero(), 20),
               ResourceLimitExceeded);
}

}  // namespace
}  // namespace skelgrasp::grasping
