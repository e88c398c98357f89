#pragma once
// A robot hand: kinematics and collision geometry from URDF, plus the grasp description that says
// how it grasps (fingers and their closing joints, preshapes with grasp centre points, interval
// lengths and planner thresholds). Lengths in metres, angles in radians. Schema: docs/hands.md.
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/grasping/grasp.h"

namespace skelgrasp::grasping {

enum class ShapeType { kBox, kSphere, kCylinder, kMesh };

struct CollisionShape {
  ShapeType type = ShapeType::kBox;
  Pose origin = Pose::Identity();  // in the link frame
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();
  double radius = 0;                         // sphere, cylinder
  double length = 0;                         // cylinder, along its z axis
  std::shared_ptr<const TriangleMesh> mesh;  // kMesh, already scaled to metres
};

enum class JointType { kFixed, kRevolute, kPrismatic };

struct Link {
  std::string name;
  int parent_joint = -1;  // -1 for the root
  std::vector<CollisionShape> shapes;
};

struct Joint {
  std::string name;
  JointType type = JointType::kFixed;
  int parent_link = -1;
  int child_link = -1;
  Pose origin = Pose::Identity();  // parent link frame -> joint frame (before motion)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double lower = 0, upper = 0;
  // URDF <mimic>: q = multiplier * q[mimic_of] + offset, always enforced.
  int mimic_of = -1;
  double mimic_multiplier = 1, mimic_offset = 0;

  bool movable() const { return type != JointType::kFixed; }
};

// Which collisions a finger link takes part in while closing (Simox semantics): kAll = object,
// other fingers and the palm/static links; kActors = object and other fingers; kNone = never.
enum class CollisionMode { kNone, kActors, kAll };

// One actuated drive of a finger: a joint advanced by direction * step per closing step, and
// followers moved with it by ratio (a tendon: when one phalanx is blocked the other goes on).
struct FingerDrive {
  int joint = -1;
  double direction = 1;
  std::vector<std::pair<int, double>> followers;  // (joint, ratio)
};

struct Finger {
  std::string name;
  std::vector<FingerDrive> drives;  // base to tip
  std::vector<std::pair<int, CollisionMode>> links;
};

struct Preshape {
  std::string name;
  Eigen::VectorXd joints;  // all joints of the model (mimics applied)
  int gcp_link = -1;
  Pose gcp_in_link = Pose::Identity();  // grasp centre point: z = approach, y = finger spread
  // The grasp type the planners close this preshape for: "power" and "precision" are their own
  // types; another preshape with a type is an alternative the planners also close at every pose
  // of that type (the SDH's "spherical", "claw", "precision_tripod" and "narrow_tripod",
  // docs/hands.md). Unset: the planners never use it.
  std::optional<GraspType> grasp_type;
  // The longest object, by GraspObject::principalLengthM(), the planners close this alternative
  // preshape on (not allowed on "power" and "precision"); unset: every object. For a preshape made
  // for small objects (the SDH's "narrow_tripod"), whose grasps on a larger object only crowd out
  // the others (docs/hands.md).
  std::optional<double> max_object_length_m;
};

// Thresholds of one grasp type on the local surface shape (paper Table II), in metres of the
// standard deviation of projected surface points (docs/hands.md, "thresholds").
struct ShapeThresholds {
  double lambda1_min_m = 0, lambda1_max_m = 1e9;
  double lambda2_min_m = 0, lambda2_max_m = 1e9;
};

struct PlannerThresholds {
  double round_ratio = 1.2;
  std::optional<ShapeThresholds> precision;  // nullopt: the hand does no such grasps
  std::optional<ShapeThresholds> power;
  double power_retreat_m = 0.015;
  // The limits of grasps of `type`; nullopt: the hand does no such grasps.
  const std::optional<ShapeThresholds>& of(GraspType type) const {
    return type == GraspType::kPrecision ? precision : power;
  }
};

struct ClosingDefaults {
  double step_rad = 0.02;
  double step_m = 0.0005;
  double palm_contact_distance_m = 0.003;
  // Contact model of the finger surfaces for the quality measure: 0 = point contacts (rigid
  // links), > 0 = soft-finger contacts with this torsional friction length (docs/hands.md).
  double torsional_friction_m = 0;
};

// Which grasps the robust ranking screens (ranking/robust_ranking.h, RobustRankingParams::
// screen_candidates).
enum class ScreenCandidates {
  // The best by pre-score (epsilon x trust) over all grasps.
  kByPreScore,
  // The best by pre-score of each preshape in turn (the preshape with the best grasp first, then
  // the next best, ...), so that every preshape the planner closed is screened. Epsilon is
  // comparable within a preshape, not across them: a power tripod's three fingertips reach a
  // larger epsilon on a ball than a narrow tripod's, yet slip more under pose error (on the SDH's
  // tennis ball the 60 best epsilons were all power tripods, r 0.73 at best, while 167 narrow
  // tripods reached up to 0.92). The default.
  kPreshapesInTurn,
  // Each preshape in turn as above, but each preshape's grasps taken by their least finger travel
  // (ranking::leastFingerTravel, the largest first; ties by pre-score) instead of by epsilon: a
  // clearance, whose rank correlation with r on the SDH's kept grasps is 0.43 at the median YCB
  // object against epsilon's 0.09. Over three seeds it lifted the SDH's top-10 r by about half a
  // point at the same time and lowered ARMAR-III's a little; the SDH's description chooses it.
  kPreshapesInTurnByTravel,
};

// "epsilon", "preshapes" or "travel" (the description's "screen_by", the CLI's
// --robustness-screen-by);
// parse throws InvalidArgument for anything else.
ScreenCandidates parseScreenCandidates(const std::string& text);
const char* toString(ScreenCandidates candidates);
// Every ScreenCandidates' name ("preshapes", "epsilon", "travel"), for a caller offering the
// choice; and the same as a phrase for an error message: "\"preshapes\", \"epsilon\" or
// \"travel\"".
const std::vector<std::string>& screenCandidateNames();
std::string screenCandidateChoices();

// The robust ranking's budget for a hand (ranking/robust_ranking.h), where the ranking's
// parameters leave it to the hand. A hand whose perturbed executions cost more screens and
// searches less, so that ranking one object stays within a few seconds; unset fields take the
// ranking's own defaults. docs/hands.md, "Ranking budget".
struct RankingBudget {
  std::optional<std::size_t> screen_grasps;  // candidates screened (0: all)
  std::optional<int> screen_samples;         // perturbed executions per screened candidate (>= 1)
  std::optional<double> refine_below_r;      // scored grasps searched for a more robust pose: r
                                             // below this, in [0, 1]
  std::optional<ScreenCandidates> screen_candidates;  // the description's "screen_by"
  std::optional<int> confirm_samples;  // more screening samples for the contenders (>= 0)
};

// How strong the hand is, for the physics judge (physics/execution.h): the force its fingers can
// press with at the fingertip, which sets each finger joint's torque limit through its lever
// (prismatic joints: the force itself). The description's "strength" section; unset: the judge's
// conservative default. `source` says where the figure comes from (a datasheet), for reports.
struct HandStrength {
  std::optional<double> fingertip_force_n;
  std::string source;
};

// Largest fingertip force a description may give (N): beyond any hand's motors.
inline constexpr double kMaxFingertipForceN = 1000.0;

class HandModel {
 public:
  // Built by the loaders below; validates the tree, the description and the preshapes.
  HandModel(std::string name, std::string title, std::vector<Link> links, std::vector<Joint> joints,
            int root_link);

  const std::string& name() const { return name_; }
  const std::string& title() const { return title_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Joint>& joints() const { return joints_; }
  int rootLink() const { return root_; }
  int linkIndex(const std::string& name) const;   // -1 if absent
  int jointIndex(const std::string& name) const;  // -1 if absent
  // Joint indices ordered root to leaves (parents before children).
  const std::vector<int>& jointOrder() const { return joint_order_; }

  // Enforces mimic joints and clamps to limits.
  void normalise(Eigen::VectorXd& q) const;
  // Pose of every link in the hand's root frame.
  std::vector<Pose> linkPoses(const Eigen::VectorXd& q) const;
  // Recomputes, in `poses` (every link's, as linkPoses gives them), the child link poses of
  // `joints` (a subsequence of jointOrder()) at `q` from their parents' poses: a finger moving
  // alone updates its own links instead of the whole hand.
  void updateLinkPoses(const Eigen::VectorXd& q, const std::vector<int>& joints,
                       std::vector<Pose>& poses) const;
  Eigen::VectorXd zeroConfiguration() const;

  // Grasp description.
  const std::vector<Finger>& fingers() const { return fingers_; }
  const std::vector<int>& palmLinks() const { return palm_links_; }
  const std::map<std::string, Preshape>& preshapes() const { return preshapes_; }
  // Throws InvalidArgument naming the known preshapes.
  const Preshape& preshape(const std::string& name) const;
  // The preshapes the planners close for grasps of `type`: the one named after the type first,
  // then (with `alternatives`) the other preshapes of that type by name. Empty when the hand has
  // none of that type. The planners ask for alternatives unless told not to or in
  // reference_compat (the reference's hands close their two preshapes only); the robust
  // refinement switches between the two main preshapes only. With `object_length_m` (the
  // object's GraspObject::principalLengthM()), an alternative whose max_object_length_m is below
  // it is left out.
  std::vector<const Preshape*> plannerPreshapes(
      GraspType type, bool alternatives = true,
      std::optional<double> object_length_m = std::nullopt) const;
  // Grasp centre point of a preshape in the root frame (at the preshape's joint values).
  Pose gcpInRoot(const Preshape& preshape) const;
  const PlannerThresholds& thresholds() const { return thresholds_; }
  double precisionIntervalM() const { return precision_interval_m_; }
  double powerIntervalM() const { return power_interval_m_; }
  const ClosingDefaults& closingDefaults() const { return closing_; }
  const RankingBudget& rankingBudget() const { return ranking_budget_; }
  const HandStrength& strength() const { return strength_; }
  // Actuated drives (one per FingerDrive) and joints that move while closing.
  int numDrives() const;
  int numMovingJoints() const;
  // For each link: the finger it belongs to (-1: static) and its collision mode.
  int fingerOfLink(int link) const { return link_finger_[link]; }
  CollisionMode modeOfLink(int link) const { return link_mode_[link]; }

  // Used by the description loader.
  void setDescription(std::vector<Finger> fingers, std::vector<int> palm_links,
                      std::map<std::string, Preshape> preshapes, PlannerThresholds thresholds,
                      double precision_interval_m, double power_interval_m,
                      ClosingDefaults closing);
  // Throws InvalidArgument for a budget outside the ranges above.
  void setRankingBudget(RankingBudget budget);
  // Throws InvalidArgument for a force that is not in (0, kMaxFingertipForceN].
  void setStrength(HandStrength strength);

 private:
  std::string name_, title_;
  std::vector<Link> links_;
  std::vector<Joint> joints_;
  int root_ = 0;
  std::vector<int> joint_order_;
  std::vector<Finger> fingers_;
  std::vector<int> palm_links_;
  std::map<std::string, Preshape> preshapes_;
  PlannerThresholds thresholds_;
  double precision_interval_m_ = 0, power_interval_m_ = 0;
  ClosingDefaults closing_;
  RankingBudget ranking_budget_;
  HandStrength strength_;
  std::vector<int> link_finger_;
  std::vector<CollisionMode> link_mode_;
};

// Loads a URDF (urdfdom; mesh geometry through assimp, resolved relative to the URDF file) and a
// grasp description (JSON). Throws IoError naming the file and the problem.
HandModel loadHand(const std::string& urdf_path, const std::string& description_path);

// The same from in-memory text; `base_dir` resolves relative mesh paths, `origin` names the
// source in error messages.
HandModel loadHandFromText(const std::string& urdf_xml, const std::string& description_json,
                           const std::string& base_dir, const std::string& origin);

// Built-in hands: armar3, sdh, shadow, parallel_gripper (files in grasping/hands/, embedded).
std::vector<std::string> builtinHandNames();
HandModel loadBuiltinHand(const std::string& name);

// A built-in hand's URDF and grasp description texts, to adapt or fuzz them; throws
// InvalidArgument for an unknown name.
struct HandFiles {
  std::string urdf;
  std::string description;
};
HandFiles builtinHandFiles(const std::string& name);

// `hand` is a built-in name or a path to a .urdf, which then needs `description_path`. Throws
// InvalidArgument for an unknown name.
HandModel resolveHand(const std::string& hand, const std::string& description_path = "");

}  // namespace skelgrasp::grasping
