// Finger advance of GraspSimulator::close: the hand's FCL geometry, the link pairs allowed to
// intersect, and the step-by-step closing of the reference implementation (fact sheet §8).
#include "simulator_internal.h"

namespace skelgrasp::grasping::internal {

HandGeometry::HandGeometry(const HandModel& hand) {
  const auto& links = hand.links();
  shapes.resize(links.size());
  links_of_finger.resize(hand.fingers().size());
  for (std::size_t l = 0; l < links.size(); ++l) {
    for (const auto& shape : links[l].shapes) {
      ShapeInstance instance;
      instance.geometry = toFclGeometry(shape);
      instance.object = std::make_unique<fcl::CollisionObjectd>(instance.geometry);
      instance.origin = shape.origin;
      instance.bounding_radius = boundingRadius(shape);
      instance.surface_samples = surfaceSamples(shape);
      shapes[l].push_back(std::move(instance));
    }
    if (shapes[l].empty()) continue;
    const int link = static_cast<int>(l);
    const int finger = hand.fingerOfLink(link);
    if (finger < 0) {
      static_links.push_back(link);
    } else if (hand.modeOfLink(link) != CollisionMode::kNone) {
      finger_links.push_back(link);
      links_of_finger[finger].push_back(link);
    }
  }
}

void placeLink(const Pose& link_pose, std::vector<ShapeInstance>& shapes) {
  for (auto& s : shapes) {
    s.object->setTransform(toFcl(link_pose * s.origin));
    s.object->computeAABB();
  }
}

namespace {

bool collide(const fcl::CollisionObjectd& a, const fcl::CollisionObjectd& b, std::size_t& queries) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  ++queries;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&a, &b, request, result);
  return result.isCollision();
}

}  // namespace

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

AllowedPairs allowedLinkPairs(const HandModel& hand, const HandGeometry& geometry,
                              std::size_t& queries) {
  AllowedPairs allowed(hand.links().size());
  const auto& shapes = geometry.shapes;
  for (int l : geometry.finger_links) {
    for (int other : geometry.finger_links) {
      if (hand.fingerOfLink(other) != hand.fingerOfLink(l) &&
          linksCollide(shapes[l], shapes[other], queries)) {
        allowed.allow(l, other);
      }
    }
    for (int s : geometry.static_links) {
      if (linksCollide(shapes[l], shapes[s], queries)) allowed.allow(l, s);
    }
  }
  return allowed;
}

namespace {

enum class Blocker { kNone, kObject, kFinger, kPalm };

// One closing: the configuration, the links the object blocked, and the moves that keep the
// configuration collision-free.
class FingerAdvance {
 public:
  FingerAdvance(const HandModel& hand, HandGeometry& geometry, const fcl::CollisionObjectd& object,
                const Pose& hand_pose, const AllowedPairs& allowed, const Eigen::VectorXd& start,
                std::size_t& queries)
      : hand_(hand),
        geometry_(geometry),
        object_(object),
        hand_pose_(hand_pose),
        allowed_(allowed),
        queries_(queries),
        q_(start),
        touched_(hand.links().size(), 0) {}

  // What blocks finger `finger` at its current placement (object contacts are noted).
  Blocker blocked(int finger) {
    auto& shapes = geometry_.shapes;
    for (int l : geometry_.links_of_finger[finger]) {
      if (linkHitsObject(shapes[l], object_, queries_)) {
        touched_[l] = 1;
        return Blocker::kObject;
      }
      for (int other : geometry_.finger_links) {
        if (hand_.fingerOfLink(other) != finger && !allowed_.allowed(l, other) &&
            linksCollide(shapes[l], shapes[other], queries_)) {
          return Blocker::kFinger;
        }
      }
      if (hand_.modeOfLink(l) == CollisionMode::kAll) {
        for (int s : geometry_.static_links) {
          if (!allowed_.allowed(l, s) && linksCollide(shapes[l], shapes[s], queries_))
            return Blocker::kPalm;
        }
      }
    }
    return Blocker::kNone;
  }

  // Only the moving finger's links change pose (a drive moves joints of its own finger).
  void placeFinger(int finger, const Eigen::VectorXd& config) {
    const auto poses = hand_.linkPoses(config);
    for (int l : geometry_.links_of_finger[finger])
      placeLink(hand_pose_ * poses[l], geometry_.shapes[l]);
  }

  // Tries q + the given (joint, amount) moves; keeps it if collision-free.
  bool tryMove(int finger, const std::vector<std::pair<int, double>>& moves) {
    Eigen::VectorXd candidate = q_;
    for (const auto& [joint, amount] : moves) candidate[joint] += amount;
    hand_.normalise(candidate);
    if ((candidate - q_).cwiseAbs().maxCoeff() < 1e-12) return false;  // at the limits
    placeFinger(finger, candidate);
    if (blocked(finger) != Blocker::kNone) {
      placeFinger(finger, q_);
      return false;
    }
    q_ = candidate;
    return true;
  }

  // One step of a drive: the drive joint with its followers; when that is blocked, a tendon keeps
  // pulling whichever phalanx is still free.
  bool stepDrive(int finger, const FingerDrive& drive, double step) {
    std::vector<std::pair<int, double>> all{{drive.joint, step}};
    for (const auto& [joint, ratio] : drive.followers) all.emplace_back(joint, ratio * step);
    bool moved = tryMove(finger, all);
    for (std::size_t k = 0; !moved && all.size() > 1 && k < all.size(); ++k) {
      moved = tryMove(finger, {all[k]});
    }
    return moved;
  }

  AdvanceResult run(const AdvanceSettings& settings) {
    AdvanceResult result;
    const auto& fingers = hand_.fingers();
    for (int pass = 0; pass < settings.max_passes; ++pass) {
      std::vector<std::vector<char>> active(fingers.size());
      for (std::size_t f = 0; f < fingers.size(); ++f)
        active[f].assign(fingers[f].drives.size(), 1);
      int iterations = 0;
      bool any_active = true;
      while (any_active && iterations < settings.max_iterations_per_pass) {
        any_active = false;
        for (std::size_t f = 0; f < fingers.size(); ++f) {
          for (std::size_t d = 0; d < fingers[f].drives.size(); ++d) {
            if (!active[f][d]) continue;
            const auto& drive = fingers[f].drives[d];
            const double step = drive.direction * stepOf(drive.joint, settings);
            if (stepDrive(static_cast<int>(f), drive, step)) {
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
    result.joints = q_;
    result.touched = touched_;
    return result;
  }

 private:
  double stepOf(int joint, const AdvanceSettings& settings) const {
    return hand_.joints()[joint].type == JointType::kPrismatic ? settings.step_m
                                                               : settings.step_rad;
  }

  const HandModel& hand_;
  HandGeometry& geometry_;
  const fcl::CollisionObjectd& object_;
  const Pose hand_pose_;
  const AllowedPairs& allowed_;
  std::size_t& queries_;
  Eigen::VectorXd q_;
  std::vector<char> touched_;
};

}  // namespace

AdvanceResult advanceFingers(const HandModel& hand, HandGeometry& geometry,
                             const fcl::CollisionObjectd& object, const Pose& hand_pose,
                             const AllowedPairs& allowed, const Eigen::VectorXd& start,
                             const AdvanceSettings& settings, std::size_t& queries) {
  FingerAdvance advance(hand, geometry, object, hand_pose, allowed, start, queries);
  return advance.run(settings);
}

}  // namespace skelgrasp::grasping::internal
