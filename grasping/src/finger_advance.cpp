// Finger advance of GraspSimulator::close: the hand's FCL geometry, the link pairs allowed to
// intersect, and the step-by-step closing of the reference implementation (fact sheet §8).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "simulator_internal.h"

namespace skelgrasp::grasping {

const char* toString(ClosingMethod method) {
  return method == ClosingMethod::kStepwise ? "stepwise" : "fast";
}

ClosingMethod parseClosingMethod(const std::string& text) {
  if (text == "stepwise") return ClosingMethod::kStepwise;
  if (text == "fast") return ClosingMethod::kFast;
  throw InvalidArgument("unknown closing method '" + text + "' (use stepwise or fast)");
}

}  // namespace skelgrasp::grasping

namespace skelgrasp::grasping::internal {

HandGeometry::HandGeometry(const HandModel& hand) : motion(hand) {
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
      instance.sphere_cover = sphereCover(shape);
      if (shape.type == ShapeType::kBox) instance.box_half = 0.5 * shape.box_size;
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

// A joint move smaller than this (radians or metres) is no move: the joints are at their limits.
constexpr double kNoJointMove = 1e-12;
// Slack (in steps) so that a room that is a whole number of steps up to rounding is not one more.
constexpr double kStepCountSlack = 1e-9;

bool collide(const fcl::CollisionObjectd& a, const fcl::CollisionObjectd& b, std::size_t& queries) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  ++queries;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&a, &b, request, result);
  return result.isCollision();
}

// Exact box gaps are asked up to this distance: farther, the covering spheres' bound suffices and
// the query would scan every triangle within reach.
constexpr double kExactGapReachM = 0.01;

// A lower bound of the distance between two placed shapes from their covering spheres.
double sphereCoverGap(const ShapeInstance& a, const ShapeInstance& b) {
  const Pose pose_a = shapePose(a), pose_b = shapePose(b);
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& [ca, ra] : a.sphere_cover) {
    const Eigen::Vector3d centre = pose_a * ca;
    for (const auto& [cb, rb] : b.sphere_cover)
      gap = std::min(gap, (centre - pose_b * cb).norm() - ra - rb);
  }
  return gap;
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

double linkObjectGap(const std::vector<ShapeInstance>& link, const DistanceField& field,
                     double needed) {
  // The spheres cost a field lookup each; the exact box gap (tens of microseconds) only runs for
  // shapes that may be within `needed`, where the spheres' slack (their bulge beyond the shape
  // plus the field's interpolation bound) would stop the advance millimetres early.
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& s : link) {
    const Pose pose = shapePose(s);
    double shape_gap = std::numeric_limits<double>::infinity();
    for (const auto& [centre, radius] : s.sphere_cover)
      shape_gap = std::min(shape_gap, field.lowerBound(pose * centre) - radius);
    if (shape_gap < needed && s.box_half) {
      shape_gap = std::max(shape_gap,
                           field.boxDistance(pose, *s.box_half, std::min(needed, kExactGapReachM)));
    }
    gap = std::min(gap, shape_gap);
  }
  return gap;
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

// Kept between a link and an obstacle after a jump: covers the tolerance of FCL's distances.
constexpr double kClearanceMarginM = 1e-5;
// Longest pause (iterations) between jump attempts of a lockstep group that could not jump.
constexpr int kMaxBackoffIterations = 16;

enum class Blocker { kNone, kObject, kFinger, kPalm };

// One closing: the configuration, the links the object blocked, and the moves that keep the
// configuration collision-free.
class FingerAdvance {
 public:
  FingerAdvance(const HandModel& hand, HandGeometry& geometry, const GraspObject& object,
                const Pose& hand_pose, const AllowedPairs& allowed, const Eigen::VectorXd& start,
                std::size_t& queries)
      : hand_(hand),
        geometry_(geometry),
        grasp_object_(object),
        object_(*object.collisionData().object),
        hand_pose_(hand_pose),
        allowed_(allowed),
        queries_(queries),
        q_(start),
        touched_(hand.links().size(), 0) {}

  // What blocks finger `finger` at its current placement (object contacts are noted).
  // `check_object` false: the object is known to be out of reach (fast closing's budget).
  Blocker blocked(int finger, bool check_object = true) {
    auto& shapes = geometry_.shapes;
    for (int l : geometry_.links_of_finger[finger]) {
      if (check_object && linkHitsObject(shapes[l], object_, queries_)) {
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
  bool tryMove(int finger, const std::vector<std::pair<int, double>>& moves,
               bool check_object = true) {
    Eigen::VectorXd candidate = q_;
    for (const auto& [joint, amount] : moves) candidate[joint] += amount;
    hand_.normalise(candidate);
    if ((candidate - q_).cwiseAbs().maxCoeff() < kNoJointMove) return false;  // at the limits
    placeFinger(finger, candidate);
    if (blocked(finger, check_object) != Blocker::kNone) {
      placeFinger(finger, q_);
      return false;
    }
    q_ = candidate;
    return true;
  }

  // One step of a drive: the drive joint with its followers; when that is blocked, a tendon keeps
  // pulling whichever phalanx is still free.
  bool stepDrive(int finger, const FingerDrive& drive, double step, bool check_object = true) {
    std::vector<std::pair<int, double>> all{{drive.joint, step}};
    for (const auto& [joint, ratio] : drive.followers) all.emplace_back(joint, ratio * step);
    bool moved = tryMove(finger, all, check_object);
    for (std::size_t k = 0; !moved && all.size() > 1 && k < all.size(); ++k) {
      moved = tryMove(finger, {all[k]}, check_object);
    }
    return moved;
  }

  AdvanceResult run(const AdvanceSettings& settings) {
    return settings.method == ClosingMethod::kFast ? runFast(settings) : runStepwise(settings);
  }

  // Fast closing: the stepwise closing's steps, but steps that provably keep every link clear of
  // everything it may hit are taken at once (conservative advancement: the exact gap against the
  // displacement bound of one step). Fingers that may meet each other within their remaining
  // travel form a group that moves in lockstep, as in the stepwise closing, so the finger that
  // blocks the other is the same; groups that cannot meet move independently.
  AdvanceResult runFast(const AdvanceSettings& settings) {
    AdvanceResult result;
    const auto& fingers = hand_.fingers();
    for (int pass = 0; pass < settings.max_passes; ++pass) {
      std::vector<Drive> drives;
      for (std::size_t f = 0; f < fingers.size(); ++f) {
        for (const auto& drive : fingers[f].drives) {
          Drive d{static_cast<int>(f), &drive, {}, 0, false};
          const double step = drive.direction * stepOf(drive.joint, settings);
          d.moves.emplace_back(drive.joint, step);
          for (const auto& [joint, ratio] : drive.followers)
            d.moves.emplace_back(joint, ratio * step);
          drives.push_back(std::move(d));
        }
      }
      const std::vector<int> group = lockstepGroups(drives);
      // Per group: iterations still provably clear of the object (no object tests needed).
      std::vector<int> object_budget(fingers.size(), 0);
      std::vector<int> retry_in(fingers.size(), 0), backoff(fingers.size(), 1);
      int iterations = 0, most_steps = 0;
      bool any_active = true;
      while (any_active) {
        any_active = false;
        for (int g = 0; g < static_cast<int>(fingers.size()); ++g) {
          std::vector<Drive*> members;
          for (auto& d : drives) {
            if (group[d.finger] == g && !d.stopped && d.steps < settings.max_iterations_per_pass)
              members.push_back(&d);
          }
          if (members.empty()) continue;
          int moved = 0;
          if (object_budget[g] <= 0 && --retry_in[g] <= 0) {
            double object_safe = 0;
            moved = jumpGroup(members, settings.max_iterations_per_pass, object_safe);
            // Blocked only by the hand itself: steps without object tests while provably clear.
            if (moved == 0) object_budget[g] = static_cast<int>(object_safe);
            // Near contact the bounds rarely allow a jump: retry after growing pauses, so the
            // crawl costs no more distance queries than steps.
            backoff[g] = moved > 0 ? 1 : std::min(2 * backoff[g], kMaxBackoffIterations);
            retry_in[g] = backoff[g];
          }
          if (moved == 0) {
            // Near an obstacle: one checked step per drive, exactly the stepwise iteration.
            const bool check_object = object_budget[g] <= 0;
            object_budget[g] = std::max(0, object_budget[g] - 1);
            for (Drive* d : members) {
              if (stepDrive(d->finger, *d->drive, d->moves.front().second, check_object)) {
                d->steps += 1;
                moved = 1;
              } else {
                d->stopped = true;
              }
            }
          }
          for (Drive* d : members) most_steps = std::max(most_steps, d->steps);
          any_active = any_active || moved > 0;
        }
        ++iterations;
      }
      result.iterations += iterations;
      result.passes = pass + 1;
      // The stepwise rule (a pass of at most two iterations): no drive moved more than one step.
      if (most_steps <= 1) break;
    }
    result.joints = q_;
    result.touched = touched_;
    return result;
  }

  AdvanceResult runStepwise(const AdvanceSettings& settings) {
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
  struct Drive {
    int finger;
    const FingerDrive* drive;
    std::vector<std::pair<int, double>> moves;  // (joint, amount) of one step
    int steps;
    bool stopped;
  };

  // Joint change of `count` steps of the moves from the current configuration (limits, mimics).
  Eigen::VectorXd changeOf(const std::vector<std::pair<int, double>>& moves, double count) const {
    Eigen::VectorXd moved = q_;
    for (const auto& [joint, amount] : moves) moved[joint] += count * amount;
    hand_.normalise(moved);
    return moved - q_;
  }

  // Steps until every joint a drive moves is at its limit.
  double stepsToLimits(const std::vector<std::pair<int, double>>& moves) const {
    double steps = 0;
    for (const auto& [joint, amount] : moves) {
      const auto& j = hand_.joints()[joint];
      const double room = amount > 0 ? j.upper - q_[joint] : q_[joint] - j.lower;
      steps = std::max(steps, std::ceil(room / std::abs(amount) - kStepCountSlack));
    }
    return steps;
  }

  // Links that may block each other: fingers other than `finger`, not allowed in the preshape.
  bool mayBlock(int link, int other_finger_link) const {
    return hand_.fingerOfLink(other_finger_link) != hand_.fingerOfLink(link) &&
           !allowed_.allowed(link, other_finger_link);
  }

  // A lower bound of the distance between two links: their AABBs when that already reaches
  // `needed`, else the exact FCL distance.
  double linkPairGap(int a, int b, double needed) {
    double gap = std::numeric_limits<double>::infinity();
    fcl::DistanceRequestd request;
    for (const auto& sa : geometry_.shapes[a]) {
      for (const auto& sb : geometry_.shapes[b]) {
        double bound = sa.object->getAABB().distance(sb.object->getAABB());
        if (bound < needed) bound = std::max(bound, sphereCoverGap(sa, sb));
        if (bound >= needed) {
          gap = std::min(gap, bound);
          continue;
        }
        fcl::DistanceResultd distance;
        ++queries_;
        fcl::distance(sa.object.get(), sb.object.get(), request, distance);
        gap = std::min(gap, distance.min_distance);
      }
    }
    return gap;
  }

  // A lower bound of the distance from a link to the object (the object's distance field).
  double objectGap(int link, double needed) {
    return linkObjectGap(geometry_.shapes[link], grasp_object_.distanceField(), needed);
  }

  // Per finger, the group it moves in lockstep with: fingers whose links may come within reach
  // of each other before all their drives reach the limits (the bound of the whole remaining
  // travel of both against their gap) share a group.
  std::vector<int> lockstepGroups(const std::vector<Drive>& drives) {
    const int fingers = static_cast<int>(hand_.fingers().size());
    std::vector<double> travel(hand_.links().size(), 0);
    for (const auto& d : drives) {
      const Eigen::VectorXd change = changeOf(d.moves, stepsToLimits(d.moves));
      for (int l : geometry_.links_of_finger[d.finger])
        travel[l] += geometry_.motion.displacement(l, change);
    }
    std::vector<int> group(fingers);
    std::iota(group.begin(), group.end(), 0);
    const auto root = [&](int f) {
      while (group[f] != f) f = group[f];
      return f;
    };
    for (int a : geometry_.finger_links) {
      for (int b : geometry_.finger_links) {
        const int fa = hand_.fingerOfLink(a), fb = hand_.fingerOfLink(b);
        if (fa >= fb || !mayBlock(a, b) || root(fa) == root(fb)) continue;
        const double reach = travel[a] + travel[b];
        if (linkPairGap(a, b, reach + kClearanceMarginM) <= reach + kClearanceMarginM)
          group[root(fb)] = root(fa);
      }
    }
    for (int f = 0; f < fingers; ++f) group[f] = root(f);
    return group;
  }

  // Moves every drive of a lockstep group by the same number of steps, as many as provably keep
  // each link clear of the object, the palm and the group's other fingers. Returns the steps
  // taken, or 0 when fewer than two are safe (stepDrive then takes one checked step per drive).
  int jumpGroup(std::vector<Drive*>& members, int max_steps, double& object_safe) {
    object_safe = 0;
    std::vector<Eigen::VectorXd> changes;
    double cap = 0;
    for (Drive* d : members) {
      changes.push_back(changeOf(d->moves, 1));
      cap = std::max(cap, std::min<double>(stepsToLimits(d->moves), max_steps - d->steps));
    }
    if (cap < 2) return 0;
    // Displacement bound of one lockstep iteration, per link of the group.
    std::map<int, double> per_step;
    for (std::size_t i = 0; i < members.size(); ++i) {
      for (int l : geometry_.links_of_finger[members[i]->finger])
        per_step[l] += geometry_.motion.displacement(l, changes[i]);
    }
    double steps = cap;
    const auto limit = [&](double gap, double rate) {
      if (rate > 0) steps = std::min(steps, std::floor((gap - kClearanceMarginM) / rate));
    };
    for (const auto& [l, rate] : per_step) {
      if (rate > 0) limit(objectGap(l, rate * steps + kClearanceMarginM), rate);
    }
    object_safe = steps;
    if (steps < 2) return 0;
    for (const auto& [l, rate] : per_step) {
      if (rate <= 0) continue;
      if (hand_.modeOfLink(l) == CollisionMode::kAll) {
        for (int s : geometry_.static_links) {
          if (!allowed_.allowed(l, s))
            limit(linkPairGap(l, s, rate * steps + kClearanceMarginM), rate);
        }
      }
      // Other fingers: moving ones of the group (each pair once) and standing ones.
      for (int other : geometry_.finger_links) {
        if (!mayBlock(l, other)) continue;
        const auto moving = per_step.find(other);
        if (moving != per_step.end() && other < l) continue;
        const double both = rate + (moving != per_step.end() ? moving->second : 0.0);
        limit(linkPairGap(l, other, both * steps + kClearanceMarginM), both);
      }
      if (steps < 2) return 0;
    }
    // Only the group's fingers move; fingers outside the group cannot be reached (lockstepGroups).
    Eigen::VectorXd candidate = q_;
    for (Drive* d : members) {
      for (const auto& [joint, amount] : d->moves) candidate[joint] += steps * amount;
    }
    hand_.normalise(candidate);
    q_ = candidate;
    std::vector<int> placed;
    for (std::size_t i = 0; i < members.size(); ++i) {
      Drive* d = members[i];
      if (changes[i].cwiseAbs().maxCoeff() < kNoJointMove) {
        d->stopped = true;  // at its limits, as the stepwise closing's first failed step
      } else {
        d->steps += static_cast<int>(steps);
      }
      if (std::find(placed.begin(), placed.end(), d->finger) == placed.end()) {
        placeFinger(d->finger, q_);
        placed.push_back(d->finger);
      }
    }
    return static_cast<int>(steps);
  }

  double stepOf(int joint, const AdvanceSettings& settings) const {
    return hand_.joints()[joint].type == JointType::kPrismatic ? settings.step_m
                                                               : settings.step_rad;
  }

  const HandModel& hand_;
  HandGeometry& geometry_;
  const GraspObject& grasp_object_;
  const fcl::CollisionObjectd& object_;
  const Pose hand_pose_;
  const AllowedPairs& allowed_;
  std::size_t& queries_;
  Eigen::VectorXd q_;
  std::vector<char> touched_;
};

}  // namespace

AdvanceResult advanceFingers(const HandModel& hand, HandGeometry& geometry,
                             const GraspObject& object, const Pose& hand_pose,
                             const AllowedPairs& allowed, const Eigen::VectorXd& start,
                             const AdvanceSettings& settings, std::size_t& queries) {
  FingerAdvance advance(hand, geometry, object, hand_pose, allowed, start, queries);
  return advance.run(settings);
}

}  // namespace skelgrasp::grasping::internal
