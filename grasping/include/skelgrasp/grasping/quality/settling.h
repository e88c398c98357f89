#pragma once
// Settling: closing a hand on an object that is free to move, quasi-statically (docs/hands.md,
// "Settling"). GraspSimulator::close holds the object still, as the paper's robustness test does;
// a real object that the fingers touch off-balance is pushed until the contacts can hold the
// squeeze. Here, after each closing that is not force closure, the squeeze the fingers apply is
// balanced as far as the friction cones allow (solveSqueezeLp), the object is moved a small step
// along what is left unbalanced (translation and rotation about its centre of mass), and the
// fingers close again from where they were, until the grasp is force closure, the squeeze is
// balanced without it, the object is wedged, or it has been pushed too far.
#include <string>

#include "skelgrasp/grasping/quality/quality.h"
#include "skelgrasp/grasping/simulation/grasp_simulator.h"

namespace skelgrasp::grasping {

struct SettlingParams {
  // Largest displacement of one settling step (m): of the centre of mass, and of a point at the
  // object's max radius by the rotation. Each step first tries twice the last one (at most step_m),
  // or half of it when the unbalanced wrench reversed; a step that would move the object into the
  // hand is halved down to min_step_m, below which the object is wedged. Hand links are over 1 cm
  // thick, so no step passes through one.
  double step_m = 0.004;
  double min_step_m = 0.00025;
  // Farthest the object may be pushed in total (m, summed steps) before the execution counts as the
  // object being pushed out of the hand: about a hand's length. A power grasp can pull an object
  // 5 cm into the palm (the SDH's, from where its fingertips first touch a 6 cm cylinder).
  double max_travel_m = 0.1;
  int max_steps = 60;
  // Only contacts within this gap push or hold the object in the squeeze. A finger link keeps its
  // contact when it was blocked by the object even if the closing then moved it away (a tendon
  // curling the phalanx behind it); such a link no longer touches. A blocked link lies within one
  // closing step of the object: 0.02 rad on a lever of at most 0.1 m.
  double pushing_distance_m = 0.003;
  // Force closure of the contacts implies a balanced squeeze (a strictly positive combination of
  // their wrenches is zero, scaled to any squeeze), so while every contact pushes (all within
  // pushing_distance_m) after a step the squeeze is solved first and an unbalanced one skips the
  // closure test: one LP per step that moves the object instead of two. (Before the first step the
  // closure test goes first: most first closings are force closure.) Outcomes are the same either
  // way (tested); off runs the closure test first on every step, for comparison (`skelgrasp bench
  // ranking`).
  bool skip_closure_test_when_unbalanced = true;
};

// How a settling ended.
enum class SettlingOutcome {
  kForceClosure,    // the contacts reached (after steps moves, possibly none) are force closure
  kBalanced,        // the squeeze is held still, but the contacts are not force closure
  kWedged,          // no step along the unbalanced wrench is free, and not force closure
  kPushedOut,       // moved max_travel_m without settling
  kStepLimit,       // max_steps taken without settling
  kTooFewContacts,  // a closing ended with fewer contacts than ClosingParams::min_contacts and
                    // no finger pushes the object
  kStartCollision,  // the open hand intersects the object at the start pose
};
const char* toString(SettlingOutcome outcome);

struct SettlingResult {
  SettlingOutcome outcome = SettlingOutcome::kTooFewContacts;
  // The last closing; its contacts are in the object frame, with the hand at `hand_pose` relative
  // to the settled object.
  ClosingResult closing;
  Pose hand_pose = Pose::Identity();
  int steps = 0;        // moves of the object
  double travel_m = 0;  // summed translation of its centre of mass
  double turn_rad = 0;  // summed rotation
  bool force_closure() const { return outcome == SettlingOutcome::kForceClosure; }
};

// Closes `preshape` at `hand_pose` (object frame) and settles the object as above. `quality`
// judges force closure and the friction cones of the squeeze (the object's centre of mass and
// torque scale, as evaluateGrasp). A closing with too few contacts still settles when some finger
// touches the object (one finger pushes it into the others); without any finger contact it ends
// kTooFewContacts. Throws InvalidArgument for non-positive steps or travel, min_step_m > step_m,
// max_steps < 0 or a negative pushing distance.
SettlingResult settleGrasp(GraspSimulator& simulator, const Pose& hand_pose,
                           const Preshape& preshape, const ClosingParams& closing,
                           const QualityParams& quality, const SettlingParams& params = {});

}  // namespace skelgrasp::grasping
