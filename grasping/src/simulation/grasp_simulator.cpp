#include "skelgrasp/grasping/simulation/grasp_simulator.h"

#include <cmath>
#include <limits>

#include "simulator_internal.h"

namespace skelgrasp::grasping {

struct GraspSimulator::Impl {
  explicit Impl(const HandModel& hand) : geometry(hand) {}
  internal::HandGeometry geometry;
  std::vector<Pose> link_poses;  // object frame, after the last update
  // The allowed link pairs depend only on the preshape's joints, not on the hand pose: the fast
  // closing reuses them (robustness samples close the same preshape a hundred times).
  std::vector<std::pair<Eigen::VectorXd, internal::AllowedPairs>> allowed_cache;
  internal::AllowedPairs allowed_now;
};

const internal::AllowedPairs& GraspSimulator::allowedPairsAt(const Eigen::VectorXd& joints,
                                                             ClosingMethod method) {
  if (method == ClosingMethod::kStepwise) {
    impl_->allowed_now = internal::allowedLinkPairs(hand_, impl_->geometry, queries_);
    return impl_->allowed_now;
  }
  for (const auto& [key, pairs] : impl_->allowed_cache) {
    if (key == joints) return pairs;
  }
  internal::AllowedPairs pairs = internal::allowedLinkPairs(hand_, impl_->geometry, queries_);
  internal::allowSeparatedPairs(hand_, impl_->geometry, joints, pairs);
  impl_->allowed_cache.emplace_back(joints, std::move(pairs));
  return impl_->allowed_cache.back().second;
}

bool GraspSimulator::allowedPairsCached(const Eigen::VectorXd& joints, ClosingMethod method) const {
  if (method == ClosingMethod::kStepwise) return false;
  for (const auto& entry : impl_->allowed_cache) {
    if (entry.first == joints) return true;
  }
  return false;
}

GraspSimulator::GraspSimulator(const HandModel& hand, const GraspObject& object)
    : hand_(hand), object_(object), impl_(std::make_unique<Impl>(hand)) {}

GraspSimulator::~GraspSimulator() = default;

Pose GraspSimulator::handPoseForGcp(const Pose& gcp_pose, const Preshape& preshape) const {
  return gcp_pose * hand_.gcpInRoot(preshape).inverse();
}

namespace {

void placeLinks(const HandModel& hand, const Pose& hand_pose, const Eigen::VectorXd& q,
                std::vector<std::vector<internal::ShapeInstance>>& shapes,
                std::vector<Pose>& link_poses) {
  link_poses = hand.linkPoses(q);
  for (std::size_t l = 0; l < link_poses.size(); ++l) {
    link_poses[l] = hand_pose * link_poses[l];
    internal::placeLink(link_poses[l], shapes[l]);
  }
}

}  // namespace

int GraspSimulator::firstLinkInCollision(const Pose& hand_pose, const Eigen::VectorXd& joints) {
  auto& shapes = impl_->geometry.shapes;
  placeLinks(hand_, hand_pose, joints, shapes, impl_->link_poses);
  for (std::size_t l = 0; l < shapes.size(); ++l) {
    if (internal::linkHitsObject(shapes[l], object_, queries_)) return static_cast<int>(l);
  }
  if (object_.closed()) {
    const auto& inside = object_.surfaceQuery();
    const auto& box = object_.bounds();
    for (std::size_t l = 0; l < shapes.size(); ++l) {
      if (shapes[l].empty()) continue;
      const Eigen::Vector3d centre = impl_->link_poses[l] * shapes[l].front().origin.translation();
      const bool in_box =
          (centre.array() >= box.min.array()).all() && (centre.array() <= box.max.array()).all();
      if (in_box && inside.contains(centre)) return static_cast<int>(l);
    }
  }
  return -1;
}

ClosingResult GraspSimulator::close(const Pose& hand_pose, const Preshape& preshape,
                                    const ClosingParams& params) {
  return closeImpl(hand_pose, preshape, preshape.joints, params);
}

ClosingResult GraspSimulator::closeFrom(const Pose& hand_pose, const Preshape& preshape,
                                        const Eigen::VectorXd& joints,
                                        const ClosingParams& params) {
  if (joints.size() != preshape.joints.size())
    throw InvalidArgument("closeFrom: the joints are not the hand's");
  return closeImpl(hand_pose, preshape, joints, params);
}

ClosingResult GraspSimulator::closeImpl(const Pose& hand_pose, const Preshape& preshape,
                                        const Eigen::VectorXd& start_joints,
                                        const ClosingParams& params) {
  ClosingResult result;
  const auto& defaults = hand_.closingDefaults();
  internal::AdvanceSettings settings;
  if ((params.step_rad && !(*params.step_rad > 0)) || (params.step_m && !(*params.step_m > 0)) ||
      (params.palm_contact_distance_m && !(*params.palm_contact_distance_m >= 0))) {
    throw InvalidArgument("close: closing steps must be > 0 and the palm contact distance >= 0");
  }
  settings.step_rad = params.step_rad.value_or(defaults.step_rad);
  settings.step_m = params.step_m.value_or(defaults.step_m);
  settings.max_passes = params.max_passes;
  settings.max_iterations_per_pass = params.max_iterations_per_pass;
  settings.method = params.method;
  settings.jump_stops_at_blocking_link = params.jump_stops_at_blocking_link;
  settings.skip_repeated_refusals = params.skip_repeated_refusals;
  settings.gap_hints = params.gap_hints;
  const double palm_distance =
      params.palm_contact_distance_m.value_or(defaults.palm_contact_distance_m);
  auto& geometry = impl_->geometry;

  Eigen::VectorXd q = start_joints;
  hand_.normalise(q);
  result.joints = q;
  // The allowed pairs are those of the preshape (a closing continued from elsewhere allows what its
  // preshape allowed), found with the shapes placed at the preshape; the fast closing keeps them
  // per preshape.
  Eigen::VectorXd preshape_q = preshape.joints;
  hand_.normalise(preshape_q);
  const internal::AllowedPairs* allowed = nullptr;
  if (q != preshape_q) {
    if (!allowedPairsCached(preshape_q, params.method))
      placeLinks(hand_, hand_pose, preshape_q, geometry.shapes, impl_->link_poses);
    allowed = &allowedPairsAt(preshape_q, params.method);
  }
  const int start = firstLinkInCollision(hand_pose, q);
  if (start >= 0) {
    result.status =
        Status::Make(StatusCode::kNoResult, "hand intersects the object in its preshape");
    result.reason = "start_collision";
    result.colliding_link = hand_.links()[start].name;
    return result;
  }

  if (!allowed) allowed = &allowedPairsAt(preshape_q, params.method);
  const internal::AdvanceResult advance = internal::advanceFingers(
      hand_, geometry, object_, hand_pose, *allowed, q, settings, queries_);
  result.iterations = advance.iterations;
  result.passes = advance.passes;
  result.joints = advance.joints;
  placeLinks(hand_, hand_pose, advance.joints, geometry.shapes, impl_->link_poses);

  // Contacts: from every finger link that was blocked by or lies on the object, and every palm
  // link within the palm contact distance; one per link, or its patch's corners.
  const bool corner_contacts = params.contact_patch == ContactPatch::kCorners;
  int links_in_contact = 0;
  auto addContact = [&](int link, bool palm, double max_distance) {
    auto contacts = internal::contactPatch(
        hand_, geometry.shapes[link], link, impl_->link_poses[link], object_, palm, max_distance,
        params.method, corner_contacts, params.gap_hints, queries_);
    if (contacts.empty()) return;
    ++links_in_contact;
    for (auto& contact : contacts) result.contacts.push_back(std::move(contact));
  };
  // Touched links only near the object (internal::kTouchedGapReachM says why).
  for (int l : geometry.finger_links) {
    addContact(l, false,
               advance.touched[l] ? internal::kTouchedGapReachM : params.contact_distance_m);
  }
  if (params.palm_contacts) {
    for (int l : hand_.palmLinks()) {
      if (!geometry.shapes[l].empty()) addContact(l, true, palm_distance);
    }
  }
  if (links_in_contact < params.min_contacts) {
    result.status = Status::Make(StatusCode::kNoResult, std::to_string(links_in_contact) +
                                                            " link(s) in contact, fewer than " +
                                                            std::to_string(params.min_contacts));
    result.reason = "too_few_contacts";
  }
  return result;
}

}  // namespace skelgrasp::grasping
