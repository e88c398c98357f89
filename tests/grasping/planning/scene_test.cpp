// Scene occupancy and the approach check.
#include "skelgrasp/grasping/planning/scene.h"

#include <gtest/gtest.h>
#include <set>

#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/planning/hypothesis.h"
#include "skelgrasp/grasping/planning/planners.h"
#include "skelgrasp/skeleton/extraction.h"
#include "test_support.h"

namespace skelgrasp::grasping {
namespace {

// A wall of points: the plane x = `x`, |y| <= half, 0 <= z <= height, 4 mm spacing.
PointCloud wall(double x, double half, double height) {
  PointCloud cloud;
  for (double y = -half; y <= half; y += 0.004) {
    for (double z = 0; z <= height; z += 0.004) cloud.points.emplace_back(x, y, z);
  }
  return cloud;
}

TEST(SceneOccupancy, RaysMarkFreeSpaceAndHitsOccupied) {
  const SceneOccupancy scene(wall(0.5, 0.1, 0.2), Eigen::Vector3d(0, 0, 0.1));
  EXPECT_TRUE(scene.isOccupied({0.5, 0.0, 0.1}));
  EXPECT_FALSE(scene.isOccupied({0.25, 0.0, 0.1}));  // seen free along the rays
  EXPECT_GT(scene.occupiedLeaves(), 1000u);
  EXPECT_GT(scene.freeLeaves(), 0u);
  const std::string path = test::tempDir("scene_bt") + "/scene.bt";
  scene.writeBinary(path);
  EXPECT_GT(std::filesystem::file_size(path), 100u);
}

TEST(SceneOccupancy, UnknownSpaceCanCountAsOccupied) {
  PointCloud floor;
  for (double x = -0.2; x <= 0.2; x += 0.004) {
    for (double y = -0.2; y <= 0.2; y += 0.004) floor.points.emplace_back(x, y, 0.0);
  }
  SceneOccupancyParams cautious;
  cautious.resolution_m = 0.01;
  cautious.unknown = UnknownSpace::kOccupied;
  AxisAlignedBox target;
  target.extend({-0.03, -0.03, 0.0});
  target.extend({0.03, 0.03, 0.1});
  // The sensor looks straight down: below the floor is unseen -> occupied; near the target: free.
  const SceneOccupancy scene(floor, Eigen::Vector3d(0, 0, 0.6), cautious, target);
  EXPECT_TRUE(scene.isOccupied({0.15, 0.15, -0.0}));
  EXPECT_FALSE(scene.isOccupied({0.0, 0.0, 0.05}));
}

TEST(SceneCheck, ApproachesThroughAWallAreRejected) {
  // A cylinder standing on z = 0 with a wall 6 cm beyond its +x side; the sensor is at -x.
  const auto hand = loadBuiltinHand("armar3");
  TriangleMesh mesh = geometry::shapes::makeCylinder(0.035, 0.2, 48, 10);
  mesh.transform(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1)));
  const GraspObject object(mesh);
  const SceneOccupancy scene(wall(0.095, 0.3, 0.35), Eigen::Vector3d(-0.8, 0, 0.3));
  const SceneChecker checker(hand, &scene, SupportPlane{Eigen::Vector4d(0, 0, 1, 0)});
  SkeletonPlannerParams params;
  params.hypothesis.scene = &checker;
  const auto plan =
      planSkeletonGrasps(hand, object, skeleton::extractSkeleton(mesh).skeleton, params);
  ASSERT_FALSE(plan.grasps.empty());
  EXPECT_GT(plan.summary.rejections.at(reason::kSceneCollision), 10u);
  EXPECT_FALSE(plan.summary.scene_collision_links.empty());
  for (const auto& g : plan.grasps) {
    // No kept grasp comes from the wall side, none from below the table, and none is in collision.
    const Eigen::Vector3d approach = g.gcp_pose.rotation().col(2);
    EXPECT_GT(approach.x(), -0.5) << "grasp " << g.id << " approaches from the wall side";
    EXPECT_FALSE(checker.check(g.hand_pose, g.joints, approach).collision);
  }
}

// Two labelled walls, one on each side of a cylinder: the map keeps each wall's label, a cleared
// copy keeps them too, and the rejected poses of a plan are counted by the wall they hit.
TEST(SceneCheck, LabelledObstaclesNameWhatAHandHit) {
  PointCloud walls = wall(0.095, 0.3, 0.35);
  walls.labels.assign(walls.size(), 7);
  const PointCloud far_wall = wall(-0.095, 0.3, 0.35);
  walls.points.insert(walls.points.end(), far_wall.points.begin(), far_wall.points.end());
  walls.labels.resize(walls.size(), 9);
  const SceneOccupancy scene(walls, Eigen::Vector3d(0, -0.8, 0.3));
  EXPECT_EQ(scene.labelAt({0.095, 0.0, 0.1}), 7u);
  EXPECT_EQ(scene.labelAt({-0.095, 0.0, 0.1}), 9u);
  EXPECT_EQ(scene.labelAt({-0.099, 0.0, 0.1}), 9u);  // a neighbouring cell's label
  EXPECT_EQ(scene.labelAt({0.0, 0.0, 0.1}), 0u);     // free space
  EXPECT_EQ(scene.withPointsCleared(wall(0.095, 0.3, 0.35))->labelAt({-0.095, 0, 0.1}), 9u);
  EXPECT_EQ(
      SceneOccupancy(wall(0.095, 0.3, 0.35), Eigen::Vector3d::Zero()).labelAt({0.095, 0, 0.1}),
      0u);  // no labels

  const auto hand = loadBuiltinHand("armar3");
  TriangleMesh mesh = geometry::shapes::makeCylinder(0.035, 0.2, 48, 10);
  mesh.transform(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.1)));
  const GraspObject object(mesh);
  const SceneChecker checker(hand, &scene, SupportPlane{Eigen::Vector4d(0, 0, 1, 0)});
  SkeletonPlannerParams params;
  params.hypothesis.scene = &checker;
  const auto plan =
      planSkeletonGrasps(hand, object, skeleton::extractSkeleton(mesh).skeleton, params);
  const auto& obstacles = plan.summary.scene_collision_obstacles;
  std::size_t counted = 0;
  for (const auto& [name, count] : obstacles) counted += count;
  EXPECT_EQ(counted, plan.summary.rejections.at(reason::kSceneCollision));
  const auto& labels = plan.summary.scene_collision_labels;
  std::size_t labelled = 0;
  for (const auto& [label, count] : labels) labelled += count;
  EXPECT_EQ(labelled, obstacles.count("octree") ? obstacles.at("octree") : 0);
  EXPECT_GT(labels.count(7) ? labels.at(7) : 0, 10u);
  EXPECT_GT(labels.count(9) ? labels.at(9) : 0, 10u);
}

// A copy limited to a region holds exactly the occupied cells of the full copy inside it (pruned
// blocks of cells included) and nothing outside.
TEST(SceneOccupancy, ARegionCopyHoldsTheOccupiedCellsInsideIt) {
  PointCloud solid;  // a 4 cm cube of points every 2 mm: whole 8-cell blocks that the tree prunes
  for (double x = 0.0; x <= 0.04; x += 0.002)
    for (double y = 0.0; y <= 0.04; y += 0.002)
      for (double z = 0.0; z <= 0.04; z += 0.002) solid.points.emplace_back(x, y, z + 0.1);
  PointCloud scene = wall(0.3, 0.2, 0.3);
  scene.points.insert(scene.points.end(), solid.points.begin(), solid.points.end());
  const SceneOccupancy map(scene, Eigen::Vector3d(-0.5, 0, 0.2));
  PointCloud own;
  own.points.emplace_back(0.0205, 0.0205, 0.1205);
  AxisAlignedBox region;
  region.extend({-0.05, -0.05, 0.05});
  region.extend({0.1, 0.1, 0.2});
  const auto full = map.withPointsCleared(own);
  const auto cropped = map.withPointsCleared(own, 1, region);
  std::size_t inside = 0;
  for (double x = -0.1; x <= 0.35; x += 0.0025) {
    for (double y = -0.1; y <= 0.15; y += 0.0025) {
      for (double z = 0.0; z <= 0.25; z += 0.0025) {
        const Eigen::Vector3d p(x + 0.0001, y + 0.0001, z + 0.0001);
        const bool in =
            (p.array() >= region.min.array()).all() && (p.array() <= region.max.array()).all();
        if (in) {
          inside += full->isOccupied(p);
          EXPECT_EQ(cropped->isOccupied(p), full->isOccupied(p)) << p.transpose();
        } else {
          EXPECT_FALSE(cropped->isOccupied(p)) << p.transpose();
        }
      }
    }
  }
  EXPECT_GT(inside, 1000u);
  EXPECT_FALSE(cropped->isOccupied({0.0205, 0.0205, 0.1205}));  // cleared
  EXPECT_TRUE(full->isOccupied({0.3, 0.0, 0.1}));               // the wall, outside the region
}

TEST(SceneCheck, TheSupportPlaneBlocksHandsBelowIt) {
  const auto hand = loadBuiltinHand("sdh");
  const SceneChecker checker(hand, nullptr, SupportPlane{Eigen::Vector4d(0, 0, 1, 0)});
  Pose above = Pose::Identity(), below = Pose::Identity();
  above.translation() = Eigen::Vector3d(0, 0, 0.3);
  below.translation() = Eigen::Vector3d(0, 0, -0.05);
  const auto q = hand.preshape("power").joints;
  // Approaching downwards from above: the pre-grasp path goes up, away from the table.
  EXPECT_FALSE(checker.check(above, q, Eigen::Vector3d(0, 0, -1)).collision);
  const auto hit = checker.check(below, q, Eigen::Vector3d(0, 0, -1));
  EXPECT_TRUE(hit.collision);
  EXPECT_EQ(hit.obstacle, "support_plane");
}

// A parallel gripper coming straight down onto a block with its grasp centre point 5 mm above the
// table: its jaw tips (8.6 mm below that point) would reach 3.6 mm into the table, beyond the
// plane's 2 mm tolerance. Lifted in 2 mm steps it closes on the block's sides above the table.
TEST(SceneCheck, HandsComingDownOntoTheTableAreLiftedOffIt) {
  const HandModel hand = loadBuiltinHand("parallel_gripper");
  constexpr double kBlockHeightM = 0.03, kCentreHeightM = 0.005;
  TriangleMesh block = geometry::shapes::makeBox(Eigen::Vector3d(0.06, 0.03, kBlockHeightM), 2);
  block.transform(Pose(Eigen::Translation3d(0, 0, kBlockHeightM / 2)));  // standing on z = 0
  const GraspObject object(block);
  GraspSimulator simulator(hand, object);
  const SceneChecker table(hand, nullptr, SupportPlane{Eigen::Vector4d(0, 0, 1, 0)});
  // Approach z straight down, the jaws closing along x = the block's 30 mm side (world y).
  Eigen::Matrix3d frame;
  frame.col(0) = Eigen::Vector3d::UnitY();
  frame.col(2) = -Eigen::Vector3d::UnitZ();
  frame.col(1) = frame.col(2).cross(frame.col(0));
  Pose gcp = Pose::Identity();
  gcp.linear() = frame;
  gcp.translation() = Eigen::Vector3d(0, 0, kCentreHeightM);
  const Preshape& preshape = hand.preshape("precision");

  HypothesisParams params;
  params.quality = withHandContactModel(params.quality, hand);  // the gripper's soft pads
  params.scene = &table;
  params.scene_lift_max_m = 0;
  const HypothesisOutcome rejected = evaluateHypothesis(simulator, gcp, preshape, params);
  EXPECT_STREQ(rejected.reason, reason::kSceneCollision);

  params.scene_lift_max_m = HypothesisParams{}.scene_lift_max_m;
  const HypothesisOutcome lifted = evaluateHypothesis(simulator, gcp, preshape, params);
  ASSERT_TRUE(lifted.grasp) << (lifted.reason ? lifted.reason : "");
  EXPECT_GE(lifted.grasp->retreat_m, params.scene_lift_step_m - 1e-12);
  EXPECT_LE(lifted.grasp->retreat_m, params.scene_lift_max_m + 1e-9);
  std::set<std::string> touching;  // a jaw pushing through its patch's corners is one link
  for (const auto& c : lifted.grasp->contacts) touching.insert(c.link);
  EXPECT_EQ(touching.size(), 2u);
  EXPECT_FALSE(table.checkPose(lifted.grasp->hand_pose, lifted.grasp->joints).collision);

  // A lift step that is not positive is the caller's mistake.
  params.scene_lift_step_m = -1;
  EXPECT_THROW(evaluateHypothesis(simulator, gcp, preshape, params), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::grasping
