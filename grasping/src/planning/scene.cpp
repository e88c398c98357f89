// OctoMap is used only in this file; FCL checks the hand against its octree and a half-space.
#include "skelgrasp/grasping/planning/scene.h"

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/halfspace.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <fstream>
#include <unordered_set>

#include "simulation/fcl_conversions.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/resources.h"

namespace skelgrasp::grasping {

namespace {

// A support plane whose normal is shorter than this (coefficients as given) has no orientation.
constexpr double kDegeneratePlaneNormal = 1e-12;

// Calibration of estimateSceneOccupancyBytes (docs/limits.md, "Scene occupancy"): `run
// osd_test2.pcd` at 10, 5 and 2.5 mm (1.2e5, 4.8e5 and 3.0e6 estimated cells; 4.8e4, 3.3e5 and
// 2.3e6 leaves after pruning) peaked at 178, 202 and 422 MiB: 70-90 bytes per estimated cell.
constexpr double kOctreeBytesPerCell = 128;
// The free-space rays go to one point per block of this many cells a side (see the constructor).
constexpr double kRayBlockCells = 4;

bool inside(const Eigen::Vector3d& p, const AxisAlignedBox& box) {
  return (p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all();
}

double volume(const AxisAlignedBox& box) {
  const Eigen::Vector3d e = box.extent();
  return e.x() * e.y() * e.z();
}

// With unknown space occupied: the box whose unseen cells count as obstacles, the scan's box
// grown to hold the target and clipped to the caller's region (the estimate and the map agree).
AxisAlignedBox unknownRegion(const PointCloud& obstacles, const AxisAlignedBox& target_box,
                             const SceneOccupancyParams& params) {
  AxisAlignedBox region = obstacles.bounds();
  if (!target_box.empty()) {
    region.extend(target_box.min);
    region.extend(target_box.max);
  }
  if (!params.region.empty()) {
    region.min = region.min.cwiseMax(params.region.min);
    region.max = region.max.cwiseMin(params.region.max);
  }
  return region;
}

}  // namespace

double estimateSceneOccupancyBytes(const PointCloud& obstacles,
                                   const Eigen::Vector3d& sensor_origin,
                                   const SceneOccupancyParams& params,
                                   const AxisAlignedBox& target_box) {
  const double r = params.resolution_m;
  if (!(r > 0)) throw InvalidArgument("scene occupancy: resolution must be positive");
  const bool clipped = !params.region.empty();
  const bool every_ray = params.unknown == UnknownSpace::kOccupied;
  const bool clip_points = clipped && !every_ray;
  // Distinct ray blocks, hashed: a collision only undercounts a ray among hundreds of thousands.
  std::unordered_set<std::uint64_t> blocks;
  AxisAlignedBox reach;  // points and sensor: every ray lies inside
  reach.extend(sensor_origin);
  double observed = 0, ray_length = 0;
  const double block = kRayBlockCells * r;
  for (const auto& p : obstacles.points) {
    if (!p.allFinite() || (clip_points && !inside(p, params.region))) continue;
    observed += 1;
    reach.extend(p);
    const double length = std::min((p - sensor_origin).norm(), params.max_range_m);
    if (every_ray) {
      ray_length += length;
      continue;
    }
    const Eigen::Array3d k = (p.array() / block).floor();
    std::uint64_t key = 1469598103934665603ull;
    for (int i = 0; i < 3; ++i) {
      key ^= static_cast<std::uint64_t>(static_cast<std::int64_t>(std::clamp(k[i], -1e15, 1e15)));
      key *= 1099511628211ull;
    }
    if (blocks.insert(key).second) ray_length += length;
  }
  const double cell_volume = r * r * r;
  double cells = observed + std::min(ray_length / r, volume(reach) / cell_volume);
  if (every_ray && !obstacles.empty()) {
    const AxisAlignedBox region = unknownRegion(obstacles, target_box, params);
    if (!region.empty()) cells += volume(region) / cell_volume;
  }
  log().debug("scene occupancy estimate: {} points, {} rays, {:.3g} cells", observed,
              every_ray ? observed : static_cast<double>(blocks.size()), cells);
  return kOctreeBytesPerCell * cells;
}

void checkSceneOccupancyMemory(const PointCloud& obstacles, const Eigen::Vector3d& sensor_origin,
                               const SceneOccupancyParams& params,
                               const AxisAlignedBox& target_box) {
  checkMemoryEstimate(fmt::format("scene occupancy octree at {:g} m resolution of {} points",
                                  params.resolution_m, obstacles.size()),
                      estimateSceneOccupancyBytes(obstacles, sensor_origin, params, target_box),
                      "--octree-resolution");
}

namespace {

// A tree with the sensor model of `source` holding only its occupied cells inside `region`, each
// at full depth (a pruned occupied leaf is expanded to the cells it covers there).
std::shared_ptr<octomap::OcTree> occupiedCellsWithin(const octomap::OcTree& source,
                                                     const AxisAlignedBox& region) {
  auto tree = std::make_shared<octomap::OcTree>(source.getResolution());
  tree->setProbHit(source.getProbHit());
  tree->setProbMiss(source.getProbMiss());
  tree->setClampingThresMin(source.getClampingThresMin());
  tree->setClampingThresMax(source.getClampingThresMax());
  tree->setOccupancyThres(source.getOccupancyThres());
  octomap::OcTreeKey low, high;
  if (!source.coordToKeyChecked(region.min.x(), region.min.y(), region.min.z(), low) ||
      !source.coordToKeyChecked(region.max.x(), region.max.y(), region.max.z(), high)) {
    // A region beyond the tree's range: the whole tree, as without one.
    return std::make_shared<octomap::OcTree>(source);
  }
  const unsigned depth = source.getTreeDepth();
  for (auto it = source.begin_leafs_bbx(low, high), end = source.end_leafs_bbx(); it != end; ++it) {
    if (!source.isNodeOccupied(*it)) continue;
    const unsigned span = 1u << (depth - it.getDepth());
    const octomap::OcTreeKey corner = it.getIndexKey();
    for (unsigned dx = 0; dx < span; ++dx) {
      for (unsigned dy = 0; dy < span; ++dy) {
        for (unsigned dz = 0; dz < span; ++dz) {
          const octomap::OcTreeKey cell(static_cast<octomap::key_type>(corner[0] + dx),
                                        static_cast<octomap::key_type>(corner[1] + dy),
                                        static_cast<octomap::key_type>(corner[2] + dz));
          bool inside = true;
          for (int a = 0; a < 3; ++a) inside = inside && cell[a] >= low[a] && cell[a] <= high[a];
          if (inside) tree->setNodeValue(cell, it->getLogOdds(), /*lazy_eval=*/true);
        }
      }
    }
  }
  tree->updateInnerOccupancy();
  return tree;
}

}  // namespace

struct SceneOccupancy::Impl {
  std::shared_ptr<octomap::OcTree> tree;
  // Obstacle label per occupied cell (SceneOccupancy's labels); shared by the cleared copies.
  using Labels = std::unordered_map<octomap::OcTreeKey, std::uint32_t, octomap::OcTreeKey::KeyHash>;
  std::shared_ptr<const Labels> labels;
};

SceneOccupancy::SceneOccupancy(const PointCloud& obstacles, const Eigen::Vector3d& sensor_origin,
                               const SceneOccupancyParams& params, const AxisAlignedBox& target_box)
    : impl_(std::make_unique<Impl>()) {
  if (!(params.resolution_m > 0))
    throw InvalidArgument("scene occupancy: resolution must be positive");
  checkSceneOccupancyMemory(obstacles, sensor_origin, params, target_box);
  Stopwatch watch;
  impl_->tree = std::make_shared<octomap::OcTree>(params.resolution_m);
  octomap::Pointcloud cloud;
  cloud.reserve(obstacles.size());
  // With unknown space occupied, rays to points beyond the region still clear cells inside it.
  const bool clipped = !params.region.empty();
  const bool clip_points = clipped && params.unknown == UnknownSpace::kFree;
  for (const auto& p : obstacles.points) {
    if (!p.allFinite()) continue;
    if (clip_points && !((p.array() >= params.region.min.array()).all() &&
                         (p.array() <= params.region.max.array()).all()))
      continue;
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                    static_cast<float>(p.z()));
  }
  if (obstacles.hasLabels()) {
    auto labels = std::make_shared<Impl::Labels>();
    for (std::size_t i = 0; i < obstacles.size(); ++i) {
      const auto& p = obstacles.points[i];
      octomap::OcTreeKey key;
      if (obstacles.labels[i] != 0 && p.allFinite() &&
          impl_->tree->coordToKeyChecked(p.x(), p.y(), p.z(), key))
        labels->emplace(key, obstacles.labels[i]);
    }
    impl_->labels = std::move(labels);
  }
  const octomap::point3d origin(static_cast<float>(sensor_origin.x()),
                                static_cast<float>(sensor_origin.y()),
                                static_cast<float>(sensor_origin.z()));
  if (params.unknown == UnknownSpace::kOccupied) {
    // Every ray: unseen space counts as an obstacle here, so free space must be exact.
    impl_->tree->insertPointCloud(cloud, origin, params.max_range_m, /*lazy_eval=*/false,
                                  /*discretize=*/true);
  } else {
    // Free space only informs the map here (unknown counts as free anyway): rays to one point per
    // 4 x 4 x 4-cell block (0.35 s instead of 1.76 s for 300k table points), then every observed
    // cell set occupied at full resolution so no ray can have cleared an obstacle.
    octomap::Pointcloud sparse;
    octomap::KeySet blocks, cells;
    // A block is the full-depth key without its low kBlockShift bits. OctoMap's own
    // coordToKey(coord, depth) left-shifts the signed key of negative coordinates (undefined
    // behaviour, reported by UBSan), so the block is derived from the checked unsigned key.
    constexpr unsigned kBlockShift = 2;  // 4 x 4 x 4 cells
    for (const auto& p : cloud) {
      octomap::OcTreeKey key;
      if (!impl_->tree->coordToKeyChecked(p, key)) continue;  // outside the tree's range
      const octomap::OcTreeKey block(key[0] >> kBlockShift, key[1] >> kBlockShift,
                                     key[2] >> kBlockShift);
      if (blocks.insert(block).second) sparse.push_back(p);
      cells.insert(key);
    }
    impl_->tree->insertPointCloud(sparse, origin, params.max_range_m, /*lazy_eval=*/false,
                                  /*discretize=*/true);
    for (const auto& key : cells)
      impl_->tree->setNodeValue(key, impl_->tree->getClampingThresMaxLog(), true);
    impl_->tree->updateInnerOccupancy();
  }
  if (params.unknown == UnknownSpace::kOccupied && !obstacles.empty()) {
    // Unseen cells of the scene's box become occupied, away from the target.
    const AxisAlignedBox region = unknownRegion(obstacles, target_box, params);
    const double r = params.resolution_m;
    const Eigen::Vector3d lo =
        target_box.empty() ? Eigen::Vector3d::Constant(1e9)
                           : Eigen::Vector3d(target_box.min.array() - params.target_clearance_m);
    const Eigen::Vector3d hi =
        target_box.empty() ? Eigen::Vector3d::Constant(-1e9)
                           : Eigen::Vector3d(target_box.max.array() + params.target_clearance_m);
    std::size_t filled = 0;
    for (double x = region.min.x(); x <= region.max.x(); x += r) {
      for (double y = region.min.y(); y <= region.max.y(); y += r) {
        for (double z = region.min.z(); z <= region.max.z(); z += r) {
          const Eigen::Vector3d p(x, y, z);
          if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) continue;
          const octomap::point3d q(static_cast<float>(x), static_cast<float>(y),
                                   static_cast<float>(z));
          if (impl_->tree->search(q) == nullptr) {
            impl_->tree->updateNode(q, true, true);
            ++filled;
          }
        }
      }
    }
    impl_->tree->updateInnerOccupancy();
    log().debug("scene occupancy: {} unseen cells marked occupied", filled);
  }
  impl_->tree->prune();
  log().debug("scene occupancy: {} points -> {} occupied / {} free leaves in {:.2f} s",
              cloud.size(), occupiedLeaves(), freeLeaves(), watch.seconds());
}

SceneOccupancy::~SceneOccupancy() = default;

std::unique_ptr<SceneOccupancy> SceneOccupancy::withPointsCleared(
    const PointCloud& points, int dilation_cells, const AxisAlignedBox& region) const {
  if (dilation_cells < 0) throw InvalidArgument("scene occupancy: negative dilation");
  std::unique_ptr<SceneOccupancy> copy(new SceneOccupancy());
  copy->impl_ = std::make_unique<Impl>();
  copy->impl_->labels = impl_->labels;
  if (!region.empty()) {
    copy->impl_->tree = occupiedCellsWithin(*impl_->tree, region);
  } else {
    copy->impl_->tree = std::make_shared<octomap::OcTree>(*impl_->tree);
  }
  auto& tree = *copy->impl_->tree;
  const float free_log_odds = tree.getClampingThresMinLog();
  octomap::KeySet cleared;
  for (const auto& p : points.points) {
    octomap::OcTreeKey key;
    if (!p.allFinite() ||
        !tree.coordToKeyChecked(static_cast<double>(p.x()), static_cast<double>(p.y()),
                                static_cast<double>(p.z()), key))
      continue;
    for (int dx = -dilation_cells; dx <= dilation_cells; ++dx) {
      for (int dy = -dilation_cells; dy <= dilation_cells; ++dy) {
        for (int dz = -dilation_cells; dz <= dilation_cells; ++dz) {
          const octomap::OcTreeKey cell(static_cast<octomap::key_type>(key[0] + dx),
                                        static_cast<octomap::key_type>(key[1] + dy),
                                        static_cast<octomap::key_type>(key[2] + dz));
          if (!cleared.insert(cell).second) continue;
          const auto* node = tree.search(cell);
          if (node != nullptr && tree.isNodeOccupied(node))
            tree.setNodeValue(cell, free_log_odds, /*lazy_eval=*/true);
        }
      }
    }
  }
  tree.updateInnerOccupancy();
  tree.prune();
  return copy;
}

std::size_t SceneOccupancy::occupiedLeaves() const {
  std::size_t n = 0;
  for (auto it = impl_->tree->begin_leafs(); it != impl_->tree->end_leafs(); ++it)
    n += impl_->tree->isNodeOccupied(*it);
  return n;
}

std::size_t SceneOccupancy::freeLeaves() const {
  std::size_t n = 0;
  for (auto it = impl_->tree->begin_leafs(); it != impl_->tree->end_leafs(); ++it)
    n += !impl_->tree->isNodeOccupied(*it);
  return n;
}

double SceneOccupancy::resolution() const {
  return impl_->tree->getResolution();
}

bool SceneOccupancy::isOccupied(const Eigen::Vector3d& p) const {
  const auto* node = impl_->tree->search(static_cast<double>(p.x()), static_cast<double>(p.y()),
                                         static_cast<double>(p.z()));
  return node != nullptr && impl_->tree->isNodeOccupied(node);
}

std::uint32_t SceneOccupancy::labelAt(const Eigen::Vector3d& p) const {
  octomap::OcTreeKey key;
  if (!impl_->labels || !impl_->tree->coordToKeyChecked(p.x(), p.y(), p.z(), key)) return 0;
  const auto labelOf = [&](const octomap::OcTreeKey& k) {
    const auto it = impl_->labels->find(k);
    return it == impl_->labels->end() ? std::uint32_t{0} : it->second;
  };
  if (const std::uint32_t own = labelOf(key)) return own;
  std::uint32_t best = 0;
  int best_distance = 4;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        const int distance = std::abs(dx) + std::abs(dy) + std::abs(dz);
        if (distance == 0 || distance >= best_distance) continue;
        const octomap::OcTreeKey cell(static_cast<octomap::key_type>(key[0] + dx),
                                      static_cast<octomap::key_type>(key[1] + dy),
                                      static_cast<octomap::key_type>(key[2] + dz));
        if (const std::uint32_t label = labelOf(cell)) {
          best = label;
          best_distance = distance;
        }
      }
    }
  }
  return best;
}

void SceneOccupancy::writeBinary(const std::string& path) const {
  // The stream overload: the file-name one also prints progress on stdout.
  writeFileAtomically(path, [this, &path](std::ostream& out) {
    // Debian's liboctomap is built with its debug output on: "Writing N nodes... done." on stderr.
    const SilencedStream quiet(SilencedStream::Stream::kStderr);
    if (!impl_->tree->writeBinaryConst(out)) throw IoError(path, "cannot write OctoMap file");
  });
}

struct SceneChecker::Impl {
  const HandModel* hand = nullptr;
  SceneCheckParams params;
  std::optional<SupportPlane> plane;
  std::unique_ptr<fcl::CollisionObjectd> octree;
  const SceneOccupancy* occupancy = nullptr;
  std::unique_ptr<fcl::CollisionObjectd> halfspace;
  // Per link: each shape's geometry and its origin in the link frame.
  std::vector<std::vector<std::pair<std::shared_ptr<fcl::CollisionGeometryd>, Pose>>> shapes;
};

SceneChecker::SceneChecker(const HandModel& hand, const SceneOccupancy* occupancy,
                           std::optional<SupportPlane> plane, const SceneCheckParams& params)
    : impl_(std::make_unique<Impl>()) {
  impl_->hand = &hand;
  impl_->params = params;
  if (occupancy) {
    auto geometry = std::make_shared<fcl::OcTreed>(occupancy->impl().tree);
    impl_->octree = std::make_unique<fcl::CollisionObjectd>(geometry);
    impl_->octree->computeAABB();
    impl_->occupancy = occupancy;
  }
  if (plane) {
    // The obstacle is the half-space below the plane: n . x <= -d - tolerance.
    Eigen::Vector3d n = plane->coefficients.head<3>();
    const double norm = n.norm();
    if (norm < kDegeneratePlaneNormal)
      throw InvalidArgument("scene check: degenerate support plane");
    n /= norm;
    impl_->plane = SupportPlane{plane->coefficients / norm};
    const double offset = -plane->coefficients[3] / norm - params.plane_tolerance_m;
    impl_->halfspace =
        std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Halfspaced>(n, offset));
  }
  impl_->shapes.resize(hand.links().size());
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    for (const auto& shape : hand.links()[l].shapes) {
      impl_->shapes[l].emplace_back(internal::toFclGeometry(shape), shape.origin);
    }
  }
}

SceneChecker::~SceneChecker() = default;

const std::optional<SupportPlane>& SceneChecker::plane() const {
  return impl_->plane;
}

SceneCheckResult SceneChecker::check(const Pose& hand_pose, const Eigen::VectorXd& q,
                                     const Eigen::Vector3d& approach) const {
  return checkPath(hand_pose, q, approach, true);
}

SceneCheckResult SceneChecker::checkPose(const Pose& hand_pose, const Eigen::VectorXd& q) const {
  return checkPath(hand_pose, q, Eigen::Vector3d::UnitZ(), false);
}

SceneCheckResult SceneChecker::checkPath(const Pose& hand_pose, const Eigen::VectorXd& q,
                                         const Eigen::Vector3d& approach, bool with_path) const {
  SceneCheckResult result;
  const auto link_poses = impl_->hand->linkPoses(q);
  const Eigen::Vector3d dir = approach.normalized();
  const int steps = with_path ? static_cast<int>(std::ceil(impl_->params.pregrasp_distance_m /
                                                           impl_->params.path_step_m))
                              : 0;
  for (int i = 0; i <= steps; ++i) {
    const double back = std::min(impl_->params.pregrasp_distance_m, i * impl_->params.path_step_m);
    const Pose pose = Eigen::Translation3d(-back * dir) * hand_pose;
    for (std::size_t l = 0; l < impl_->shapes.size(); ++l) {
      for (const auto& [shape, origin] : impl_->shapes[l]) {
        // A placed copy sharing the shape's geometry: the planners check poses from several
        // threads at once, so the checker's own objects are never moved.
        fcl::CollisionObjectd placed(shape, internal::toFcl(pose * link_poses[l] * origin));
        placed.computeAABB();
        for (const auto* obstacle : {impl_->octree.get(), impl_->halfspace.get()}) {
          if (!obstacle) continue;
          const bool octree = obstacle == impl_->octree.get();
          fcl::CollisionRequestd request;
          // In a labelled map the contact names the obstacle hit; it is computed for the one
          // colliding check that ends the path.
          request.enable_contact = octree && impl_->occupancy->impl().labels != nullptr;
          fcl::CollisionResultd hit;
          fcl::collide(&placed, obstacle, request, hit);
          if (hit.isCollision()) {
            result.collision = true;
            result.link = impl_->hand->links()[l].name;
            result.obstacle = octree ? "octree" : "support_plane";
            if (request.enable_contact && hit.numContacts() > 0)
              result.obstacle_label = impl_->occupancy->labelAt(hit.getContact(0).pos);
            result.distance_m = back;
            return result;
          }
        }
      }
    }
  }
  return result;
}

}  // namespace skelgrasp::grasping
