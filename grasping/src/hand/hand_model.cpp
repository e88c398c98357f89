#include "skelgrasp/grasping/hand/hand_model.h"

#include <deque>
#include <utility>

#include "skelgrasp/common/error.h"

namespace skelgrasp::grasping {

HandModel::HandModel(std::string name, std::string title, std::vector<Link> links,
                     std::vector<Joint> joints, int root_link)
    : name_(std::move(name)),
      title_(std::move(title)),
      links_(std::move(links)),
      joints_(std::move(joints)),
      root_(root_link) {
  if (links_.empty()) throw InvalidArgument("hand '" + name_ + "': no links");
  if (root_ < 0 || root_ >= static_cast<int>(links_.size())) {
    throw InvalidArgument("hand '" + name_ + "': bad root link");
  }
  // Breadth-first order from the root; every link must be reached exactly once.
  std::vector<std::vector<int>> children(links_.size());
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const auto& joint = joints_[j];
    if (joint.parent_link < 0 || joint.child_link < 0) {
      throw InvalidArgument("hand '" + name_ + "': joint '" + joint.name + "' is not connected");
    }
    children[joint.parent_link].push_back(static_cast<int>(j));
    if (joint.mimic_of >= static_cast<int>(joints_.size())) {
      throw InvalidArgument("hand '" + name_ + "': joint '" + joint.name +
                            "' mimics an unknown joint");
    }
  }
  std::vector<char> reached(links_.size(), 0);
  reached[root_] = 1;
  std::deque<int> queue{root_};
  while (!queue.empty()) {
    const int link = queue.front();
    queue.pop_front();
    for (int j : children[link]) {
      const int child = joints_[j].child_link;
      if (reached[child])
        throw InvalidArgument("hand '" + name_ + "': kinematic loop at '" + links_[child].name +
                              "'");
      reached[child] = 1;
      joint_order_.push_back(j);
      queue.push_back(child);
    }
  }
  for (std::size_t l = 0; l < links_.size(); ++l) {
    if (!reached[l])
      throw InvalidArgument("hand '" + name_ + "': link '" + links_[l].name +
                            "' is not connected to the root");
  }
  link_finger_.assign(links_.size(), -1);
  link_mode_.assign(links_.size(), CollisionMode::kAll);
}

int HandModel::linkIndex(const std::string& name) const {
  for (std::size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int HandModel::jointIndex(const std::string& name) const {
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    if (joints_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

Eigen::VectorXd HandModel::zeroConfiguration() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints_.size()));
  normalise(q);
  return q;
}

void HandModel::normalise(Eigen::VectorXd& q) const {
  SKELGRASP_DEMAND(q.size() == static_cast<Eigen::Index>(joints_.size()));
  for (int j : joint_order_) {
    const auto& joint = joints_[j];
    if (!joint.movable()) {
      q[j] = 0;
      continue;
    }
    if (joint.mimic_of >= 0) q[j] = joint.mimic_multiplier * q[joint.mimic_of] + joint.mimic_offset;
    q[j] = std::clamp(q[j], joint.lower, joint.upper);
  }
}

std::vector<Pose> HandModel::linkPoses(const Eigen::VectorXd& q) const {
  std::vector<Pose> poses(links_.size(), Pose::Identity());
  updateLinkPoses(q, joint_order_, poses);
  return poses;
}

void HandModel::updateLinkPoses(const Eigen::VectorXd& q, const std::vector<int>& joints,
                                std::vector<Pose>& poses) const {
  SKELGRASP_DEMAND(q.size() == static_cast<Eigen::Index>(joints_.size()));
  SKELGRASP_DEMAND(poses.size() == links_.size());
  for (int j : joints) {
    const auto& joint = joints_[j];
    Pose motion = Pose::Identity();
    if (joint.type == JointType::kRevolute) {
      motion.linear() = Eigen::AngleAxisd(q[j], joint.axis).toRotationMatrix();
    } else if (joint.type == JointType::kPrismatic) {
      motion.translation() = joint.axis * q[j];
    }
    poses[joint.child_link] = poses[joint.parent_link] * joint.origin * motion;
  }
}

const Preshape& HandModel::preshape(const std::string& name) const {
  const auto it = preshapes_.find(name);
  if (it == preshapes_.end()) {
    std::string known;
    for (const auto& [n, p] : preshapes_) known += (known.empty() ? "" : ", ") + n;
    throw InvalidArgument("hand '" + name_ + "' has no preshape '" + name + "' (known: " + known +
                          ")");
  }
  return it->second;
}

std::vector<const Preshape*> HandModel::plannerPreshapes(
    GraspType type, bool alternatives, std::optional<double> object_length_m) const {
  const auto fits = [&](const Preshape& preshape) {
    return !object_length_m || !preshape.max_object_length_m ||
           *object_length_m <= *preshape.max_object_length_m;
  };
  std::vector<const Preshape*> out;
  const auto main = preshapes_.find(toString(type));
  if (main != preshapes_.end()) out.push_back(&main->second);
  if (!alternatives) return out;
  for (const auto& [name, preshape] : preshapes_) {
    if (preshape.grasp_type == type && name != toString(type) && fits(preshape))
      out.push_back(&preshape);
  }
  return out;
}

Pose HandModel::gcpInRoot(const Preshape& preshape) const {
  return linkPoses(preshape.joints)[preshape.gcp_link] * preshape.gcp_in_link;
}

int HandModel::numDrives() const {
  int n = 0;
  for (const auto& f : fingers_) n += static_cast<int>(f.drives.size());
  return n;
}

int HandModel::numMovingJoints() const {
  int n = 0;
  for (const auto& f : fingers_) {
    for (const auto& d : f.drives) n += 1 + static_cast<int>(d.followers.size());
  }
  return n;
}

void HandModel::setDescription(std::vector<Finger> fingers, std::vector<int> palm_links,
                               std::map<std::string, Preshape> preshapes,
                               PlannerThresholds thresholds, double precision_interval_m,
                               double power_interval_m, ClosingDefaults closing) {
  fingers_ = std::move(fingers);
  palm_links_ = std::move(palm_links);
  preshapes_ = std::move(preshapes);
  thresholds_ = thresholds;
  precision_interval_m_ = precision_interval_m;
  power_interval_m_ = power_interval_m;
  closing_ = closing;
  link_finger_.assign(links_.size(), -1);
  link_mode_.assign(links_.size(), CollisionMode::kAll);
  for (std::size_t f = 0; f < fingers_.size(); ++f) {
    for (const auto& [link, mode] : fingers_[f].links) {
      if (link_finger_[link] >= 0) {
        throw InvalidArgument("hand '" + name_ + "': link '" + links_[link].name +
                              "' is in two fingers");
      }
      link_finger_[link] = static_cast<int>(f);
      link_mode_[link] = mode;
    }
  }
}

namespace {
// Every screening order with its name, in the order the names are offered: the one table the
// parser, toString, the descriptions' and the command line's choices read.
constexpr std::pair<ScreenCandidates, const char*> kScreenCandidateNames[] = {
    {ScreenCandidates::kPreshapesInTurn, "preshapes"},
    {ScreenCandidates::kByPreScore, "epsilon"},
    {ScreenCandidates::kPreshapesInTurnByTravel, "travel"},
};
}  // namespace

const std::vector<std::string>& screenCandidateNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const auto& [candidates, name] : kScreenCandidateNames) all.emplace_back(name);
    return all;
  }();
  return names;
}

std::string screenCandidateChoices() {
  const auto& names = screenCandidateNames();
  std::string choices;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) choices += i + 1 == names.size() ? " or " : ", ";
    choices += "\"" + names[i] + "\"";
  }
  return choices;
}

ScreenCandidates parseScreenCandidates(const std::string& text) {
  for (const auto& [candidates, name] : kScreenCandidateNames)
    if (text == name) return candidates;
  throw InvalidArgument("unknown screening candidates '" + text + "' (use " +
                        screenCandidateChoices() + ")");
}

const char* toString(ScreenCandidates candidates) {
  for (const auto& [known, name] : kScreenCandidateNames)
    if (known == candidates) return name;
  return "?";
}

void HandModel::setStrength(HandStrength strength) {
  if (strength.fingertip_force_n &&
      !(*strength.fingertip_force_n > 0 && *strength.fingertip_force_n <= kMaxFingertipForceN)) {
    throw InvalidArgument("hand '" + name_ + "': strength fingertip_force_n must be in (0, " +
                          std::to_string(static_cast<int>(kMaxFingertipForceN)) + "] N");
  }
  strength_ = std::move(strength);
}

void HandModel::setRankingBudget(RankingBudget budget) {
  if (budget.screen_samples && *budget.screen_samples < 1)
    throw InvalidArgument("hand '" + name_ + "': ranking screen_samples must be >= 1");
  if (budget.confirm_samples && *budget.confirm_samples < 0)
    throw InvalidArgument("hand '" + name_ + "': ranking confirm_samples must be >= 0");
  if (budget.refine_below_r && !(*budget.refine_below_r >= 0 && *budget.refine_below_r <= 1))
    throw InvalidArgument("hand '" + name_ + "': ranking refine_below_r must be in [0, 1]");
  ranking_budget_ = budget;
}

}  // namespace skelgrasp::grasping
