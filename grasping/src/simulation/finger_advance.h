#pragma once
// The finger advance of GraspSimulator::close as a class shared by its two translation units:
// finger_advance.cpp (geometry, collision tests, the stepwise closing) and finger_advance_fast.cpp
// (the fast closing's jumps and the gap bounds behind them).
#include <utility>
#include <vector>

#include "simulator_internal.h"

namespace skelgrasp::grasping::internal {

// A joint move smaller than this (radians or metres) is no move: the joints are at their limits.
constexpr double kNoJointMove = 1e-12;
// Slack (in steps) so that a room that is a whole number of steps up to rounding is not one more.
constexpr double kStepCountSlack = 1e-9;

// A lower bound of the distance between two placed shapes from their covering spheres.
double sphereCoverGap(const ShapeInstance& a, const ShapeInstance& b);

enum class Blocker { kNone, kObject, kFinger, kPalm, kLimits };

// What refused a move; `finger` is the other finger when `by` is kFinger (else -1).
struct Block {
  Blocker by = Blocker::kNone;
  int finger = -1;
};

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
        hand_pose_(hand_pose),
        allowed_(allowed),
        queries_(queries),
        q_(start),
        poses_(hand.linkPoses(start)),
        touched_(hand.links().size(), 0),
        moved_(hand.links().size(), 0.0),
        per_step_(hand.links().size(), 0.0),
        in_jump_(hand.links().size(), 0) {
    geometry_.kept_gaps.startClosing();
  }

  // What blocks finger `finger` at its current placement (object contacts are noted).
  // `check_object` false: the object is known to be out of reach (fast closing's budget).
  // `change`: the joint change that placed the finger, for the fast closing's gap bounds.
  Block blocked(int finger, bool check_object, const Eigen::VectorXd& change) {
    auto& shapes = geometry_.shapes;
    for (int l : geometry_.links_of_finger[finger]) {
      if (check_object && !provablyClearOfObject(l, change) &&
          linkHitsObject(shapes[l], grasp_object_, queries_)) {
        touched_[l] = 1;
        return {Blocker::kObject};
      }
      for (int other : geometry_.finger_links) {
        if (hand_.fingerOfLink(other) != finger && !allowed_.allowed(l, other) &&
            linksCollide(shapes[l], shapes[other], queries_)) {
          return {Blocker::kFinger, hand_.fingerOfLink(other)};
        }
      }
      if (hand_.modeOfLink(l) == CollisionMode::kAll) {
        for (int s : geometry_.static_links) {
          if (!allowed_.allowed(l, s) && linksCollide(shapes[l], shapes[s], queries_))
            return {Blocker::kPalm};
        }
      }
    }
    return {};
  }

  // Only the moving finger's links change pose (a drive moves joints of its own finger).
  void placeFinger(int finger, const Eigen::VectorXd& config) {
    hand_.updateLinkPoses(config, geometry_.joints_moved_by_finger[finger], poses_);
    for (int l : geometry_.links_of_finger[finger])
      placeLink(hand_pose_ * poses_[l], geometry_.shapes[l]);
  }

  // Tries q + the given (joint, amount) moves; keeps it if collision-free (then by kNone), else
  // says what refused it.
  Block tryMove(int finger, const std::vector<std::pair<int, double>>& moves,
                bool check_object = true) {
    // candidate_ and change_ are scratch kept across steps: a closing takes thousands of checked
    // steps, and two heap vectors per step were a few percent of its time.
    candidate_ = q_;
    for (const auto& [joint, amount] : moves) candidate_[joint] += amount;
    hand_.normalise(candidate_);
    change_ = candidate_ - q_;
    if (change_.cwiseAbs().maxCoeff() < kNoJointMove) return {Blocker::kLimits};
    placeFinger(finger, candidate_);
    const Block block = blocked(finger, check_object, change_);
    if (block.by != Blocker::kNone) {
      placeFinger(finger, q_);
      return block;
    }
    noteMove(finger, change_);
    q_.swap(candidate_);
    return block;
  }

  // One step of a drive: the drive joint with its followers; when that is blocked, a tendon keeps
  // pulling whichever phalanx is still free.
  // `blockers`, when given and the step is refused: the other fingers that refused one of the
  // moves tried (the object, the palm and the joint limits refused the rest).
  bool stepDrive(int finger, const FingerDrive& drive, double step, bool check_object = true,
                 std::vector<int>* blockers = nullptr) {
    auto& all = step_moves_;
    all.assign(1, {drive.joint, step});
    for (const auto& [joint, ratio] : drive.followers) all.emplace_back(joint, ratio * step);
    if (blockers) blockers->clear();
    // Whether the move went through; if not, notes the finger that refused it.
    const auto moves = [&](const Block& block) {
      if (blockers && block.finger >= 0) blockers->push_back(block.finger);
      return block.by == Blocker::kNone;
    };
    bool moved = moves(tryMove(finger, all, check_object));
    for (std::size_t k = 0; !moved && all.size() > 1 && k < all.size(); ++k) {
      single_move_.assign(1, all[k]);
      moved = moves(tryMove(finger, single_move_, check_object));
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
  AdvanceResult runFast(const AdvanceSettings& settings);

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
    int steps;                                  // in this pass
    bool stopped;                               // in this pass
    // AdvanceSettings::skip_repeated_refusals: (joint, value) of the placing joints of its finger
    // and of the fingers that refused its last refused step; empty when none is known or the drive
    // has moved since.
    std::vector<std::pair<int, double>> refused_at;
  };

  // AdvanceSettings::skip_repeated_refusals: a refused checked step is refused again while the
  // placing joints of its finger and of the fingers that refused it keep their values (the same
  // link placements against the same obstacles: the object and the palm do not move), so a later
  // pass stops the drive without the collision tests. The stepwise closing tests it again: the
  // same verdict.
  bool knownRefused(const Drive& d) const;
  void noteRefusal(Drive& d, const std::vector<int>& blockers) const;

  // Joint change of `count` steps of the moves from the current configuration (limits, mimics),
  // written to `change`.
  void changeOf(const std::vector<std::pair<int, double>>& moves, double count,
                Eigen::VectorXd& change) const;

  // Steps until every joint a drive moves is at its limit.
  double stepsToLimits(const std::vector<std::pair<int, double>>& moves) const;

  // Pairs whose gap bounds a jump: all but those allowed to intersect, so also those that provably
  // never meet (allowSeparatedPairs). Only the checked steps skip the latter's collision tests:
  // letting the jumps ignore them too made ARMAR-III's closing slower (1.9 against 1.5 ms, paired
  // runs of the two builds): jumps past adjacent fingers end nearer the object, where the group's
  // exact gaps are dearer.
  bool boundsJump(int link, int other) const;
  // Links that may block each other or bound a jump: fingers other than `finger` (boundsJump).
  bool mayBlock(int link, int other_finger_link) const;

  // A lower bound of the distance between two links: their AABBs when that already reaches
  // `needed`, else the exact FCL distance.
  double linkPairGap(int a, int b, double needed);

  double computeLinkPairGap(int a, int b, double needed);

  // A lower bound of the distance from a link to the object (the object's distance field).
  double objectGap(int link, double needed, bool gap_hints);

  // Whether a gap bound kept from a fast closing's jump attempt, less this move's displacement
  // bound, still proves the placed link clear of the object, so that its collision test would
  // find nothing. The stepwise closing keeps no bounds and tests every link.
  bool provablyClearOfObject(int link, const Eigen::VectorXd& change) const;

  // Adds the displacement bound of the joint change `change` (about to be applied to q_) to every
  // link of `finger`: the cached gaps stay lower bounds.
  void noteMove(int finger, const Eigen::VectorXd& change);

  // Per finger, the group it moves in lockstep with: fingers whose links may come within reach
  // of each other before all their drives reach the limits (the bound of the whole remaining
  // travel of both against their gap) share a group.
  std::vector<int> lockstepGroups(const std::vector<Drive>& drives);

  // Moves every drive of a lockstep group by the same number of steps, as many as provably keep
  // each link clear of the object, the palm and the group's other fingers. Returns the steps
  // taken, or 0 when fewer than two are safe (stepDrive then takes one checked step per drive).
  // `settings`: the steps' limit per pass and whether an attempt stops at the first link that
  // allows no step (AdvanceSettings::jump_stops_at_blocking_link).
  int jumpGroup(std::vector<Drive*>& members, const AdvanceSettings& settings, double& object_safe);

  double stepOf(int joint, const AdvanceSettings& settings) const {
    return hand_.joints()[joint].type == JointType::kPrismatic ? settings.step_m
                                                               : settings.step_rad;
  }

  const HandModel& hand_;
  HandGeometry& geometry_;
  const GraspObject& grasp_object_;
  const Pose hand_pose_;
  const AllowedPairs& allowed_;
  std::size_t& queries_;
  Eigen::VectorXd q_;
  // Link poses (hand frame) as last placed: each finger's at the configuration it was placed in
  // (q_ or a candidate about to be tested); only the placed finger's change.
  std::vector<Pose> poses_;
  std::vector<char> touched_;
  // Per link: summed displacement bounds of its moves so far, against which the gap bounds this
  // closing keeps (geometry_.kept_gaps) stay valid.
  std::vector<double> moved_;

  // Scratch reused across steps and jump attempts of one closing (no heap work per step).
  Eigen::VectorXd candidate_, change_;
  std::vector<std::pair<int, double>> step_moves_, single_move_;
  std::vector<Eigen::VectorXd> jump_changes_;
  std::vector<double> per_step_;  // per link: displacement bound of one lockstep iteration
  std::vector<char> in_jump_;     // per link: a link of the jumping fingers
  std::vector<int> jump_links_;   // those links, ascending
  // A moving link of a jump attempt (AdvanceSettings::jump_stops_at_blocking_link's order).
  struct Moving {
    double kept_steps;  // the link's kept gap bound in steps (infinite when none is kept)
    int link;
    double rate;  // its displacement bound per iteration
  };
  std::vector<Moving> jump_moving_;
};

}  // namespace skelgrasp::grasping::internal
