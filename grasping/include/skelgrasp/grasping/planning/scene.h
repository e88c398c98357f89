#pragma once
// The grasp's surroundings: an occupancy octree (OctoMap) of the scene points that are not the
// target object, built by inserting them as rays from the sensor so free space is known, plus the
// support plane as a half-space. Grasps whose hand hits either — at the final pose or along the
// approach from a pre-grasp distance — are rejected with reason "scene_collision".
#include <memory>
#include <optional>
#include <string>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/point_cloud.h"
#include "skelgrasp/grasping/grasp.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

namespace reason {
inline constexpr const char* kSceneCollision = "scene_collision";
}

enum class UnknownSpace {
  kFree,      // cells no ray has seen count as free (default: the occluded back of the target and
              // the space under an unseen part of the table would otherwise block most grasps)
  kOccupied,  // cautious: unseen cells within the scene's bounding box count as occupied, except
              // within `target_clearance_m` of the target box (which holds the unseen back side)
};

struct SceneOccupancyParams {
  double resolution_m = 0.005;
  double max_range_m = 4.0;  // rays longer than this are cut (free up to the range, no hit)
  UnknownSpace unknown = UnknownSpace::kFree;
  double target_clearance_m = 0.03;
  // Only obstacle points inside this box are inserted (empty box: all). A hand grasping the target
  // never reaches farther than its size plus the pre-grasp distance, and ray casting the whole
  // scene cost 1.8 s of a 3.5 s run on the demo scene.
  AxisAlignedBox region;
};

// Memory estimate (bytes) of building SceneOccupancy from these arguments:
//   cells = ray cells + observed cells (+ with UnknownSpace::kOccupied, the region's volume / r^3),
//   ray cells = min(sum of ray lengths / r, volume of the box holding points and sensor / r^3)
// where rays go from the sensor to one point per 4 x 4 x 4-cell block (every point with unknown
// space occupied), each cut at max_range_m, and bytes = kOctreeBytesPerCell x cells (leaf, inner
// nodes and OctoMap's key sets during insertion), fitted to /usr/bin/time -v peak RSS of
// `skelgrasp run` at several resolutions (docs/limits.md).
double estimateSceneOccupancyBytes(const PointCloud& obstacles,
                                   const Eigen::Vector3d& sensor_origin,
                                   const SceneOccupancyParams& params = {},
                                   const AxisAlignedBox& target_box = {});
// Throws ResourceLimitExceeded (common/resources.h) when that exceeds the memory limit.
void checkSceneOccupancyMemory(const PointCloud& obstacles, const Eigen::Vector3d& sensor_origin,
                               const SceneOccupancyParams& params = {},
                               const AxisAlignedBox& target_box = {});

class SceneOccupancy {
 public:
  // `obstacles` in the scan frame; rays start at `sensor_origin`. `target_box` (scan frame) is only
  // used for UnknownSpace::kOccupied. With labels (one per point, 0 = none), each occupied cell
  // keeps the label of its first point: the scene check names what a hand hit (labelAt). Throws
  // InvalidArgument for a non-positive resolution and ResourceLimitExceeded when
  // estimateSceneOccupancyBytes exceeds the memory limit.
  SceneOccupancy(const PointCloud& obstacles, const Eigen::Vector3d& sensor_origin,
                 const SceneOccupancyParams& params = {}, const AxisAlignedBox& target_box = {});
  ~SceneOccupancy();
  SceneOccupancy(const SceneOccupancy&) = delete;
  SceneOccupancy& operator=(const SceneOccupancy&) = delete;

  // A copy in which the cells holding `points`, and their neighbours up to `dilation_cells` away,
  // are free. One map of a whole scene serves each of its objects: the object's own points are
  // cleared from its copy, so its grasps meet the table and the other objects but not itself
  // (copying costs a fraction of the ray insertion). With a `region`, the copy holds only the
  // occupied cells inside it (free and unknown cells both count as free to the scene check): an
  // object's workspace, so that each object of a large scene copies its surroundings, not the
  // whole scene. Throws InvalidArgument for negative dilation.
  std::unique_ptr<SceneOccupancy> withPointsCleared(const PointCloud& points,
                                                    int dilation_cells = 1,
                                                    const AxisAlignedBox& region = {}) const;

  std::size_t occupiedLeaves() const;
  std::size_t freeLeaves() const;
  double resolution() const;
  bool isOccupied(const Eigen::Vector3d& point) const;
  // The label of the obstacle points in the cell holding `point`, or else in the nearest of its
  // 26 neighbours that has one (a contact lies on a cell's surface); 0 when none.
  std::uint32_t labelAt(const Eigen::Vector3d& point) const;
  // OctoMap binary file (.bt). Throws IoError.
  void writeBinary(const std::string& path) const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  SceneOccupancy() = default;  // for withPointsCleared
  std::unique_ptr<Impl> impl_;
};

// A support plane a x + b y + c z + d = 0 with the object on the positive side.
struct SupportPlane {
  Eigen::Vector4d coefficients = Eigen::Vector4d(0, 0, 1, 0);
};

struct SceneCheckParams {
  double pregrasp_distance_m = 0.10;  // the approach starts this far back along -approach
  double path_step_m = 0.005;
  double plane_tolerance_m = 0.002;  // hand geometry may dip this far below the plane
};

struct SceneCheckResult {
  bool collision = false;
  std::string link;                  // first colliding link
  std::string obstacle;              // "octree" or "support_plane"
  std::uint32_t obstacle_label = 0;  // octree: SceneOccupancy::labelAt the contact (0 = none)
  double distance_m = 0;             // along the approach path, from the final pose back
};

// Checks a hand (in the scan frame, at `hand_pose` in configuration `q`) and its straight approach
// from the pre-grasp distance. Either of occupancy / plane may be absent. The checks only read the
// checker: the planners call them from several threads at once.
class SceneChecker {
 public:
  SceneChecker(const HandModel& hand, const SceneOccupancy* occupancy,
               std::optional<SupportPlane> plane, const SceneCheckParams& params = {});
  ~SceneChecker();
  // The support plane with a unit normal (pointing to the object's side), if any: the fallback
  // planner's "top" strategy approaches against it.
  const std::optional<SupportPlane>& plane() const;
  SceneCheckResult check(const Pose& hand_pose, const Eigen::VectorXd& q,
                         const Eigen::Vector3d& approach) const;
  // The hand at `hand_pose` in configuration `q` only, without the approach path (the closed
  // hand: its fingers close around the object where the open hand was checked).
  SceneCheckResult checkPose(const Pose& hand_pose, const Eigen::VectorXd& q) const;

 private:
  SceneCheckResult checkPath(const Pose& hand_pose, const Eigen::VectorXd& q,
                             const Eigen::Vector3d& approach, bool with_path) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace skelgrasp::grasping
