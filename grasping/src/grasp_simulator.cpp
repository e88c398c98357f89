#include "skelgrasp/grasping/grasp_simulator.h"

#include <cmath>
#include <limits>

#include "fcl_conversions.h"

namespace skelgrasp::grasping {
namespace {

struct ShapeInstance {
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  std::unique_ptr<fcl::CollisionObjectd> object;
  Pose origin;
  double bounding_radius = 0;  // about the shape's origin
};

enum class Blocker { kNone, kObject, kFinger, kPalm };

// Points on a shape's surface in its own frame: box corners, edge midpoints and face centres;
// sphere and cylinder points on their axes and rims; up to 64 mesh vertices.
std::vector<Eigen::Vector3d> surfaceSamples(const CollisionShape& shape) {
  std::vector<Eigen::Vector3d> samples;
  switch (shape.type) {
    case ShapeType::kBox:
      for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
          for (int z = -1; z <= 1; ++z) {
            if (x || y || z)
              samples.push_back(0.5 * shape.box_size.cwiseProduct(Eigen::Vector3d(x, y, z)));
          }
        }
      }
      break;
    case ShapeType::kSphere:
      for (int a = 0; a < 3; ++a) {
        for (int sign : {-1, 1}) samples.push_back(sign * shape.radius * Eigen::Vector3d::Unit(a));
      }
      break;
    case ShapeType::kCylinder:
      for (double z : {-0.5, 0.0, 0.5}) {
        if (z != 0.0) samples.emplace_back(0, 0, z * shape.length);
        for (int k = 0; k < 8; ++k) {
          const double a = k * 3.14159265358979 / 4;
          samples.emplace_back(shape.radius * std::cos(a), shape.radius * std::sin(a),
                               z * shape.length);
        }
      }
      break;
    case ShapeType::kMesh: {
      const auto& v = shape.mesh->vertices;
      const std::size_t stride = std::max<std::size_t>(1, v.size() / 64);
      for (std::size_t i = 0; i < v.size(); i += stride) samples.push_back(v[i]);
      break;
    }
  }
  return samples;
}

double boundingRadius(const CollisionShape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      return 0.5 * shape.box_size.norm();
    case ShapeType::kSphere:
      return shape.radius;
    case ShapeType::kCylinder:
      return std::hypot(shape.radius, 0.5 * shape.length);
    case ShapeType::kMesh: {
      double r = 0;
      for (const auto& v : shape.mesh->vertices) r = std::max(r, v.norm());
      return r;
    }
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

struct GraspSimulator::Impl {
  std::vector<std::vector<ShapeInstance>> shapes;  // per link
  std::vector<int> finger_links;                   // links of fingers that take part in collisions
  std::vector<int> static_links;                   // links with geometry outside every finger
  std::vector<std::vector<int>> links_of_finger;
  std::vector<Pose> link_poses;  // object frame, after the last update
};

GraspSimulator::GraspSimulator(const HandModel& hand, const GraspObject& object)
    : hand_(hand), object_(object), impl_(std::make_unique<Impl>()) {
  const auto& links = hand_.links();
  impl_->shapes.resize(links.size());
  impl_->links_of_finger.resize(hand_.fingers().size());
  for (std::size_t l = 0; l < links.size(); ++l) {
    for (const auto& shape : links[l].shapes) {
      ShapeInstance instance;
      instance.geometry = internal::toFclGeometry(shape);
      instance.object = std::make_unique<fcl::CollisionObjectd>(instance.geometry);
      instance.origin = shape.origin;
      instance.bounding_radius = boundingRadius(shape);
      impl_->shapes[l].push_back(std::move(instance));
    }
    if (impl_->shapes[l].empty()) continue;
    const int finger = hand_.fingerOfLink(static_cast<int>(l));
    if (finger < 0) {
      impl_->static_links.push_back(static_cast<int>(l));
    } else if (hand_.modeOfLink(static_cast<int>(l)) != CollisionMode::kNone) {
      impl_->finger_links.push_back(static_cast<int>(l));
      impl_->links_of_finger[finger].push_back(static_cast<int>(l));
    }
  }
}

GraspSimulator::~GraspSimulator() = default;

Pose GraspSimulator::handPoseForGcp(const Pose& gcp_pose, const Preshape& preshape) const {
  return gcp_pose * hand_.gcpInRoot(preshape).inverse();
}

namespace {

void placeLink(const Pose& link_pose, std::vector<ShapeInstance>& shapes) {
  for (auto& s : shapes) {
    s.object->setTransform(internal::toFcl(link_pose * s.origin));
    s.object->computeAABB();
  }
}

void placeLinks(const HandModel& hand, const Pose& hand_pose, const Eigen::VectorXd& q,
                std::vector<std::vector<ShapeInstance>>& shapes, std::vector<Pose>& link_poses) {
  link_poses = hand.linkPoses(q);
  for (std::size_t l = 0; l < link_poses.size(); ++l) {
    link_poses[l] = hand_pose * link_poses[l];
    placeLink(link_poses[l], shapes[l]);
  }
}

bool collide(const fcl::CollisionObjectd& a, const fcl::CollisionObjectd& b, std::size_t& queries) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  ++queries;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&a, &b, request, result);
  return result.isCollision();
}

bool linksCollide(const std::vector<ShapeInstance>& a, const std::vector<ShapeInstance>& b,
                  std::size_t& queries) {
  for (const auto& sa : a) {
    for (const auto& sb : b) {
      if (collide(*sa.object, *sb.object, queries)) return true;
    }
  }
  return false;
}

bool linkHitsObject(const std::vector<ShapeInstance>& link, const fcl::CollisionObjectd& object,
                    std::size_t& queries) {
  for (const auto& s : link) {
    if (collide(*s.object, object, queries)) return true;
  }
  return false;
}

}  // namespace

int GraspSimulator::firstLinkInCollision(const Pose& hand_pose, const Eigen::VectorXd& joints) {
  placeLinks(hand_, hand_pose, joints, impl_->shapes, impl_->link_poses);
  const auto& object = *object_.collisionData().object;
  for (std::size_t l = 0; l < impl_->shapes.size(); ++l) {
    if (linkHitsObject(impl_->shapes[l], object, queries_)) return static_cast<int>(l);
  }
  if (object_.closed()) {
    const auto& inside = object_.surfaceQuery();
    const auto& box = object_.bounds();
    for (std::size_t l = 0; l < impl_->shapes.size(); ++l) {
      if (impl_->shapes[l].empty()) continue;
      const Eigen::Vector3d centre =
          impl_->link_poses[l] * impl_->shapes[l].front().origin.translation();
      const bool in_box =
          (centre.array() >= box.min.array()).all() && (centre.array() <= box.max.array()).all();
      if (in_box && inside.contains(centre)) return static_cast<int>(l);
    }
  }
  return -1;
}

ClosingResult GraspSimulator::close(const Pose& hand_pose, const Preshape& preshape,
                                    const ClosingParams& params) {
  ClosingResult result;
  const auto& defaults = hand_.closingDefaults();
  const double step_rad = params.step_rad > 0 ? params.step_rad : defaults.step_rad;
  const double step_m = params.step_m > 0 ? params.step_m : defaults.step_m;
  const double palm_distance = params.palm_contact_distance_m >= 0
                                   ? params.palm_contact_distance_m
                                   : defaults.palm_contact_distance_m;
  const auto& object = *object_.collisionData().object;
  auto& shapes = impl_->shapes;

  Eigen::VectorXd q = preshape.joints;
  hand_.normalise(q);
  result.joints = q;
  const int start = firstLinkInCollision(hand_pose, q);
  if (start >= 0) {
    result.status =
        Status::Make(StatusCode::kNoResult, "hand intersects the object in its preshape");
    result.reason = "start_collision";
    result.colliding_link = hand_.links()[start].name;
    return result;
  }

  // Link pairs already intersecting in the preshape are attached by design (a finger mounted in
  // the palm box); they are not checked while closing.
  const std::size_t n = hand_.links().size();
  std::vector<char> allowed(n * n, 0);
  for (int l : impl_->finger_links) {
    for (int other : impl_->finger_links) {
      if (hand_.fingerOfLink(other) != hand_.fingerOfLink(l) &&
          linksCollide(shapes[l], shapes[other], queries_)) {
        allowed[l * n + other] = 1;
      }
    }
    for (int s : impl_->static_links) {
      if (linksCollide(shapes[l], shapes[s], queries_)) allowed[l * n + s] = 1;
    }
  }

  std::vector<char> touched(n, 0);
  // Collision of finger f's links after a move: returns what blocked it (object contacts noted).
  auto blocked = [&](int finger) {
    for (int l : impl_->links_of_finger[finger]) {
      if (linkHitsObject(shapes[l], object, queries_)) {
        touched[l] = 1;
        return Blocker::kObject;
      }
      for (int other : impl_->finger_links) {
        if (hand_.fingerOfLink(other) != finger && !allowed[l * n + other] &&
            linksCollide(shapes[l], shapes[other], queries_)) {
          return Blocker::kFinger;
        }
      }
      if (hand_.modeOfLink(l) == CollisionMode::kAll) {
        for (int s : impl_->static_links) {
          if (!allowed[l * n + s] && linksCollide(shapes[l], shapes[s], queries_))
            return Blocker::kPalm;
        }
      }
    }
    return Blocker::kNone;
  };
  auto stepOf = [&](int joint) {
    return hand_.joints()[joint].type == JointType::kPrismatic ? step_m : step_rad;
  };
  // Only the moving finger's links change pose (a drive moves joints of its own finger).
  auto placeFinger = [&](int finger, const Eigen::VectorXd& config) {
    const auto poses = hand_.linkPoses(config);
    for (int l : impl_->links_of_finger[finger]) placeLink(hand_pose * poses[l], shapes[l]);
  };
  // Tries q + delta on the given (joint, amount) moves; keeps it if collision-free.
  auto tryMove = [&](int finger, const std::vector<std::pair<int, double>>& moves) {
    Eigen::VectorXd candidate = q;
    for (const auto& [joint, amount] : moves) candidate[joint] += amount;
    hand_.normalise(candidate);
    if ((candidate - q).cwiseAbs().maxCoeff() < 1e-12) return false;  // at the limits
    placeFinger(finger, candidate);
    if (blocked(finger) != Blocker::kNone) {
      placeFinger(finger, q);
      return false;
    }
    q = candidate;
    return true;
  };

  const auto& fingers = hand_.fingers();
  for (int pass = 0; pass < params.max_passes; ++pass) {
    std::vector<std::vector<char>> active(fingers.size());
    for (std::size_t f = 0; f < fingers.size(); ++f) active[f].assign(fingers[f].drives.size(), 1);
    int iterations = 0;
    bool any_active = true;
    while (any_active && iterations < params.max_iterations_per_pass) {
      any_active = false;
      for (std::size_t f = 0; f < fingers.size(); ++f) {
        for (std::size_t d = 0; d < fingers[f].drives.size(); ++d) {
          if (!active[f][d]) continue;
          const auto& drive = fingers[f].drives[d];
          const double step = drive.direction * stepOf(drive.joint);
          std::vector<std::pair<int, double>> all{{drive.joint, step}};
          for (const auto& [joint, ratio] : drive.followers) all.emplace_back(joint, ratio * step);
          bool moved = tryMove(static_cast<int>(f), all);
          // A tendon keeps pulling whichever phalanx is still free.
          for (std::size_t k = 0; !moved && all.size() > 1 && k < all.size(); ++k) {
            moved = tryMove(static_cast<int>(f), {all[k]});
          }
          if (moved) {
            any_active = true;
          } else {
            active[f][d] = 0;
          }
        }
      }
      ++iterations;
    }
    result.iterations += iterations;
    result.passes = pass + 1;
    if (iterations <= 2) break;
  }
  result.joints = q;
  placeLinks(hand_, hand_pose, q, shapes, impl_->link_poses);

  // Contacts: one per finger link that was blocked by or lies on the object, plus palm links
  // within the palm contact distance. FCL gives the exact gap but an arbitrary point of a flat
  // contact patch (a pad on a face), so the point is the centre of the patch: the object points
  // closest to the link's surface samples that lie within 1 mm of the gap.
  const auto& surface = object_.surfaceQuery();
  const auto link_poses = hand_.linkPoses(q);
  auto addContact = [&](int link, bool palm, double max_distance) {
    const Pose link_pose = hand_pose * link_poses[link];
    if (std::isfinite(max_distance)) {
      // A link whose bounding spheres all stay farther than max_distance from the surface cannot
      // be in contact: one closest-point query instead of an exact FCL distance, which dominated
      // closing.
      bool near = false;
      for (const auto& s : shapes[link]) {
        const Eigen::Vector3d centre = link_pose * s.origin.translation();
        near = near || surface.distance(centre) <= s.bounding_radius + max_distance;
      }
      if (!near) return;
    }
    fcl::DistanceRequestd request(true);
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector3d object_point = Eigen::Vector3d::Zero(), link_point = Eigen::Vector3d::Zero();
    for (const auto& s : shapes[link]) {
      fcl::DistanceResultd distance;
      ++queries_;
      // The object goes first: FCL 0.7 reports mesh-shape pairs with the mesh as object 1 (b1,
      // nearest_points[0]) whatever the argument order.
      fcl::distance(&object, s.object.get(), request, distance);
      if (distance.min_distance < best) {
        best = distance.min_distance;
        object_point = distance.nearest_points[0];
        link_point = distance.nearest_points[1];
      }
    }
    if (best > max_distance) return;
    const double gap = std::max(0.0, best);
    // FCL's point is only a fallback: on a flat patch it is any point, and it would bias the mean.
    Eigen::Vector3d patch_sum = Eigen::Vector3d::Zero(), link_sum = Eigen::Vector3d::Zero();
    int patch_count = 0;
    for (const auto& shape : hand_.links()[link].shapes) {
      for (const auto& sample : surfaceSamples(shape)) {
        const Eigen::Vector3d p = link_pose * shape.origin * sample;
        const Eigen::Vector3d closest = surface.closestPoint(p);
        if ((p - closest).norm() <= gap + 0.001) {
          patch_sum += closest;
          link_sum += p;
          ++patch_count;
        }
      }
    }
    if (patch_count == 0) {
      patch_sum = object_point;
      link_sum = link_point;
      patch_count = 1;
    }
    Contact contact;
    const auto [point, face] = surface.closestPointAndFace(patch_sum / patch_count);
    contact.point = point;
    contact.normal = object_.surfaceNormal(point, face, link_sum / patch_count - point);
    contact.link = hand_.links()[link].name;
    contact.palm = palm;
    contact.distance = gap;
    result.contacts.push_back(contact);
  };
  for (int l : impl_->finger_links) {
    addContact(l, false,
               touched[l] ? std::numeric_limits<double>::infinity() : params.contact_distance_m);
  }
  if (params.palm_contacts) {
    for (int l : hand_.palmLinks()) {
      if (!shapes[l].empty()) addContact(l, true, palm_distance);
    }
  }
  if (static_cast<int>(result.contacts.size()) < params.min_contacts) {
    result.status = Status::Make(StatusCode::kNoResult, std::to_string(result.contacts.size()) +
                                                            " contact(s), fewer than " +
                                                            std::to_string(params.min_contacts));
    result.reason = "too_few_contacts";
  }
  return result;
}

}  // namespace skelgrasp::grasping
