#pragma once
// Closing a hand on an object: collision queries and the finger-closing procedure of the
// reference implementation (fact sheet §8), with FCL collision checks.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/grasping/contact.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/simulation/grasp_object.h"

namespace skelgrasp::grasping {
namespace internal {
class AllowedPairs;
}

// How the fingers advance (docs/hands.md, "Closing").
enum class ClosingMethod {
  kStepwise,  // one step per drive and iteration, a collision test per step (the reference's way)
  kFast,      // the same steps, but the steps that provably stay clear of every obstacle (by the
              // exact distance and the links' levers about the joint axes) are taken at once
};
const char* toString(ClosingMethod method);
// "stepwise" or "fast"; throws InvalidArgument otherwise.
ClosingMethod parseClosingMethod(const std::string& text);

// A link's touching patch: the object's points nearest the link's surface samples within this
// distance (m) beyond the link's gap.
inline constexpr double kContactPatchBandM = 0.001;
// A patch narrower than this (m) is one contact at its centre (a fingertip's rounded pad), also
// under ContactPatch::kCorners.
inline constexpr double kMinCornerPatchSpanM = 0.004;

// Where a link that touches the object over an area pushes (docs/hands.md, "Contacts").
enum class ContactPatch {
  kCentre,   // one contact per link, at the patch's centre: the reference's model (fact sheet §8)
  kCorners,  // a patch spanning at least kMinCornerPatchSpanM pushes through its corners, up to
             // four contacts per link (the polyhedral model of a face contact)
};
const char* toString(ContactPatch patch);
// "centre" or "corners"; throws InvalidArgument otherwise.
ContactPatch parseContactPatch(const std::string& text);
// The model a command's or binding's options ask for: with reference_compat (which judges as the
// reference code) kCentre, the reference's one contact per link, whatever `text` says; else
// parseContactPatch(text).
ContactPatch contactPatchFor(const std::string& text, bool reference_compat);

struct ClosingParams {
  // Unset: the hand's closing defaults (its grasp description; 0.02 rad, 0.5 mm, 3 mm when it
  // gives none), resolved in GraspSimulator::close. A set value must be > 0 (distance >= 0).
  std::optional<double> step_rad;  // revolute step per iteration
  std::optional<double> step_m;    // prismatic step per iteration
  // Palm (static) links within this distance of the object add contacts.
  std::optional<double> palm_contact_distance_m;
  bool palm_contacts = true;
  // Finger links this close to the object count as touching even if they were never blocked.
  double contact_distance_m = 0.001;
  // Fewest links (fingers or palm) in contact for a closing to count; a link pushing through the
  // corners of its patch is one.
  int min_contacts = 2;
  ContactPatch contact_patch = ContactPatch::kCorners;
  // Re-runs from the reached configuration let fingers blocked by other fingers continue.
  int max_passes = 10;
  int max_iterations_per_pass = 5000;
  // Fast: the same verdicts as stepwise on 1040 real poses of the four hands, its contacts 2-4x
  // cheaper; the advance alone is still ~0.8x on ARMAR-III's bench grasps (docs/hands.md,
  // "Closing: fast or stepwise"). Stepwise stays selectable (`--closing stepwise`).
  ClosingMethod method = ClosingMethod::kFast;
  // Fast closing: a jump attempt bounds the links nearest the object first and gives up at the
  // first that allows no step (the Shadow hand's thumb sliding along the object refuses most
  // attempts so), instead of measuring every moving link's gap. The same closings either way; off
  // for `skelgrasp bench ranking --compare jump-order`.
  bool jump_stops_at_blocking_link = true;
  // Fast closing: a drive whose step was refused is not tested again in a later pass while its
  // finger, and any finger that refused it, stand where they stood (the object and the palm do not
  // move: the same test, the same verdict). The same closings either way; off for `skelgrasp bench
  // ranking --compare refusals`.
  bool skip_repeated_refusals = true;
  // Fast closing: each exact box gap of a link shape starts from the shape's last one: at the same
  // pose its answer is read again, elsewhere the face it was found at bounds the gap before the
  // search (DistanceField::boxGapAndFace's hint). The same gaps and closest faces either way; off
  // for `skelgrasp bench ranking --compare gap-hints`.
  bool gap_hints = true;
};

struct ClosingResult {
  // kOk: closed with >= min_contacts links in contact. kNoResult with reason "start_collision" (the
  // hand intersects the object in its preshape; `colliding_link` says where) or "too_few_contacts".
  Status status;
  std::string reason;
  std::string colliding_link;
  Eigen::VectorXd joints;  // reached configuration (all joints)
  std::vector<Contact> contacts;
  int iterations = 0;
  int passes = 0;
};

class GraspSimulator {
 public:
  // Keeps references: hand and object must outlive the simulator. Builds FCL objects for the
  // hand's link shapes; the object's BVH is shared.
  GraspSimulator(const HandModel& hand, const GraspObject& object);
  ~GraspSimulator();
  GraspSimulator(const GraspSimulator&) = delete;
  GraspSimulator& operator=(const GraspSimulator&) = delete;

  const HandModel& hand() const { return hand_; }
  const GraspObject& object() const { return object_; }

  // `hand_pose` is the pose of the hand's root link in the object frame.
  // First link (index) of the hand intersecting the object, or -1. A link entirely inside a closed
  // object touches no triangle; it counts as a collision too (the centre of its first shape is
  // tested for containment).
  int firstLinkInCollision(const Pose& hand_pose, const Eigen::VectorXd& joints);
  bool inCollision(const Pose& hand_pose, const Eigen::VectorXd& joints) {
    return firstLinkInCollision(hand_pose, joints) >= 0;
  }

  // Sets the preshape, then advances the fingers until they are blocked or at their limits, and
  // collects contacts.
  ClosingResult close(const Pose& hand_pose, const Preshape& preshape,
                      const ClosingParams& params = {});
  // Continues a closing of `preshape` from the configuration `joints` (one an earlier closing
  // reached, at another hand pose: settling.h): as close(), with the link pairs the preshape allows
  // to intersect, but the fingers start at `joints`. The start test is at `joints`.
  ClosingResult closeFrom(const Pose& hand_pose, const Preshape& preshape,
                          const Eigen::VectorXd& joints, const ClosingParams& params = {});

  // Hand root pose that puts the preshape's grasp centre point at `gcp_pose` (object frame).
  Pose handPoseForGcp(const Pose& gcp_pose, const Preshape& preshape) const;

  std::size_t collisionQueries() const { return queries_; }

 private:
  struct Impl;
  // The shapes must be placed at `joints` (any hand pose).
  const internal::AllowedPairs& allowedPairsAt(const Eigen::VectorXd& joints, ClosingMethod method);
  bool allowedPairsCached(const Eigen::VectorXd& joints, ClosingMethod method) const;
  // close() and closeFrom(): the allowed pairs of `preshape`, the fingers starting at `start`.
  ClosingResult closeImpl(const Pose& hand_pose, const Preshape& preshape,
                          const Eigen::VectorXd& start, const ClosingParams& params);
  const HandModel& hand_;
  const GraspObject& object_;
  std::unique_ptr<Impl> impl_;
  std::size_t queries_ = 0;
};

}  // namespace skelgrasp::grasping
