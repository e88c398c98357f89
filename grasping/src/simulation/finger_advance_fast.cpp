// The fast closing (docs/hands.md, "Closing"): the stepwise closing's steps,
// but those that provably keep every link clear are taken at once, bounded by gaps that stay
// valid while the links move.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "finger_advance.h"

namespace skelgrasp::grasping::internal {
namespace {

// Kept between a link and an obstacle after a jump: covers the tolerance of FCL's distances.
constexpr double kClearanceMarginM = 1e-5;
// Longest pause (iterations) between jump attempts of a lockstep group that could not jump.
constexpr int kMaxBackoffIterations = 16;

}  // namespace

// Fast closing: the stepwise closing's steps, but steps that provably keep every link clear of
// everything it may hit are taken at once (conservative advancement: the exact gap against the
// displacement bound of one step). Fingers that may meet each other within their remaining
// travel form a group that moves in lockstep, as in the stepwise closing, so the finger that
// blocks the other is the same; groups that cannot meet move independently.
AdvanceResult FingerAdvance::runFast(const AdvanceSettings& settings) {
  AdvanceResult result;
  const auto& fingers = hand_.fingers();
  std::vector<Drive> drives;
  for (std::size_t f = 0; f < fingers.size(); ++f) {
    for (const auto& drive : fingers[f].drives) {
      Drive d{static_cast<int>(f), &drive, {}, 0, false, {}};
      const double step = drive.direction * stepOf(drive.joint, settings);
      d.moves.emplace_back(drive.joint, step);
      for (const auto& [joint, ratio] : drive.followers) d.moves.emplace_back(joint, ratio * step);
      drives.push_back(std::move(d));
    }
  }
  for (int pass = 0; pass < settings.max_passes; ++pass) {
    // Every drive starts again; what refused it is remembered across passes.
    for (Drive& d : drives) {
      d.steps = 0;
      d.stopped = false;
    }
    const std::vector<int> group = lockstepGroups(drives);
    // Per group: iterations still provably clear of the object (no object tests needed).
    std::vector<int> object_budget(fingers.size(), 0);
    std::vector<int> retry_in(fingers.size(), 0), backoff(fingers.size(), 1);
    int iterations = 0, most_steps = 0;
    bool any_active = true;
    std::vector<int> blockers;
    std::vector<Drive*> members;
    members.reserve(drives.size());
    while (any_active) {
      any_active = false;
      for (int g = 0; g < static_cast<int>(fingers.size()); ++g) {
        members.clear();
        for (auto& d : drives) {
          if (group[d.finger] == g && !d.stopped && d.steps < settings.max_iterations_per_pass)
            members.push_back(&d);
        }
        if (members.empty()) continue;
        int moved = 0;
        if (object_budget[g] <= 0 && --retry_in[g] <= 0) {
          double object_safe = 0;
          moved = jumpGroup(members, settings, object_safe);
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
            if (settings.skip_repeated_refusals && knownRefused(*d)) {
              d->stopped = true;
              continue;
            }
            if (stepDrive(d->finger, *d->drive, d->moves.front().second, check_object, &blockers)) {
              d->steps += 1;
              d->refused_at.clear();
              moved = 1;
            } else {
              d->stopped = true;
              if (settings.skip_repeated_refusals) noteRefusal(*d, blockers);
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

bool FingerAdvance::knownRefused(const Drive& d) const {
  if (d.refused_at.empty()) return false;
  for (const auto& [joint, value] : d.refused_at) {
    if (q_[joint] != value) return false;
  }
  return true;
}

void FingerAdvance::noteRefusal(Drive& d, const std::vector<int>& blockers) const {
  d.refused_at.clear();
  const auto watch = [&](int finger) {
    for (int j : geometry_.joints_placing_finger[finger]) d.refused_at.emplace_back(j, q_[j]);
  };
  watch(d.finger);
  for (int f : blockers) watch(f);
}

void FingerAdvance::changeOf(const std::vector<std::pair<int, double>>& moves, double count,
                             Eigen::VectorXd& change) const {
  change = q_;
  for (const auto& [joint, amount] : moves) change[joint] += count * amount;
  hand_.normalise(change);
  change -= q_;
}

double FingerAdvance::stepsToLimits(const std::vector<std::pair<int, double>>& moves) const {
  double steps = 0;
  for (const auto& [joint, amount] : moves) {
    const auto& j = hand_.joints()[joint];
    const double room = amount > 0 ? j.upper - q_[joint] : q_[joint] - j.lower;
    steps = std::max(steps, std::ceil(room / std::abs(amount) - kStepCountSlack));
  }
  return steps;
}

bool FingerAdvance::boundsJump(int link, int other) const {
  return !allowed_.intersecting(link, other);
}

bool FingerAdvance::mayBlock(int link, int other_finger_link) const {
  return hand_.fingerOfLink(other_finger_link) != hand_.fingerOfLink(link) &&
         boundsJump(link, other_finger_link);
}

double FingerAdvance::linkPairGap(int a, int b, double needed) {
  const auto [first, second] = std::minmax(a, b);
  auto& kept = geometry_.kept_gaps;
  if (const GapBound* bound = kept.pair(first, second)) {
    const double current = bound->current(moved_[first], moved_[second]);
    if (current >= needed) return current;
  }
  const double gap = computeLinkPairGap(a, b, needed);
  kept.keepPair(first, second, {gap, moved_[first], moved_[second]});
  return gap;
}

double FingerAdvance::computeLinkPairGap(int a, int b, double needed) {
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

double FingerAdvance::objectGap(int link, double needed, bool gap_hints) {
  auto& kept = geometry_.kept_gaps;
  if (const GapBound* bound = kept.object(link)) {
    const double current = bound->current(moved_[link], 0.0);
    if (current >= needed) return current;
  }
  const double gap =
      linkObjectGap(geometry_.shapes[link], grasp_object_.distanceField(), needed, gap_hints);
  kept.keepObject(link, {gap, moved_[link], 0.0});
  return gap;
}

bool FingerAdvance::provablyClearOfObject(int link, const Eigen::VectorXd& change) const {
  const GapBound* kept = geometry_.kept_gaps.object(link);
  if (!kept) return false;
  const double moved = moved_[link] + geometry_.motion.displacement(link, change);
  return kept->current(moved, 0.0) > kClearanceMarginM;
}

void FingerAdvance::noteMove(int finger, const Eigen::VectorXd& change) {
  for (int l : geometry_.links_of_finger[finger])
    moved_[l] += geometry_.motion.displacement(l, change);
}

std::vector<int> FingerAdvance::lockstepGroups(const std::vector<Drive>& drives) {
  const int fingers = static_cast<int>(hand_.fingers().size());
  std::vector<double> travel(hand_.links().size(), 0);
  for (const auto& d : drives) {
    changeOf(d.moves, stepsToLimits(d.moves), change_);
    for (int l : geometry_.links_of_finger[d.finger])
      travel[l] += geometry_.motion.displacement(l, change_);
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

int FingerAdvance::jumpGroup(std::vector<Drive*>& members, const AdvanceSettings& settings,
                             double& object_safe) {
  const int max_steps = settings.max_iterations_per_pass;
  const bool stop_at_blocking_link = settings.jump_stops_at_blocking_link;
  object_safe = 0;
  auto& changes = jump_changes_;
  if (changes.size() < members.size()) changes.resize(members.size());
  double cap = 0;
  for (std::size_t i = 0; i < members.size(); ++i) {
    changeOf(members[i]->moves, 1, changes[i]);
    cap = std::max(
        cap, std::min<double>(stepsToLimits(members[i]->moves), max_steps - members[i]->steps));
  }
  if (cap < 2) return 0;
  // Displacement bound of one lockstep iteration, per link of the group (jump_links_, ascending).
  for (int l : jump_links_) {
    per_step_[l] = 0;
    in_jump_[l] = 0;
  }
  jump_links_.clear();
  for (std::size_t i = 0; i < members.size(); ++i) {
    for (int l : geometry_.links_of_finger[members[i]->finger]) {
      if (!in_jump_[l]) {
        in_jump_[l] = 1;
        jump_links_.push_back(l);
      }
      per_step_[l] += geometry_.motion.displacement(l, changes[i]);
    }
  }
  std::sort(jump_links_.begin(), jump_links_.end());
  double steps = cap;
  const auto limit = [&](double gap, double rate) {
    if (rate > 0) steps = std::min(steps, std::floor((gap - kClearanceMarginM) / rate));
  };
  // AdvanceSettings::jump_stops_at_blocking_link: the links nearest the object first (by their
  // kept gap bounds, in steps), and none after one that allows no step: the others' gaps, exact
  // queries near the object, could not allow one. That changes nothing but the work: no step is
  // taken and the object budget is the same (none).
  auto& moving = jump_moving_;
  moving.clear();
  for (int l : jump_links_) {
    const double rate = per_step_[l];
    if (!(rate > 0)) continue;
    const GapBound* kept = geometry_.kept_gaps.object(l);
    moving.push_back(
        {kept ? kept->current(moved_[l], 0.0) / rate : std::numeric_limits<double>::infinity(), l,
         rate});
  }
  if (stop_at_blocking_link) {
    // Ties in link order, the order they were listed in: a stable sort without its buffer.
    std::sort(moving.begin(), moving.end(), [](const Moving& a, const Moving& b) {
      return a.kept_steps < b.kept_steps || (a.kept_steps == b.kept_steps && a.link < b.link);
    });
  }
  for (const Moving& m : moving) {
    limit(objectGap(m.link, m.rate * steps + kClearanceMarginM, settings.gap_hints), m.rate);
    if (stop_at_blocking_link && steps <= 0) break;
  }
  object_safe = steps;
  if (steps < 2) return 0;
  for (int l : jump_links_) {
    const double rate = per_step_[l];
    if (rate <= 0) continue;
    if (hand_.modeOfLink(l) == CollisionMode::kAll) {
      for (int s : geometry_.static_links) {
        if (boundsJump(l, s)) limit(linkPairGap(l, s, rate * steps + kClearanceMarginM), rate);
      }
    }
    // Other fingers: moving ones of the group (each pair once) and standing ones.
    for (int other : geometry_.finger_links) {
      if (!mayBlock(l, other)) continue;
      if (in_jump_[other] && other < l) continue;
      const double both = rate + (in_jump_[other] ? per_step_[other] : 0.0);
      limit(linkPairGap(l, other, both * steps + kClearanceMarginM), both);
    }
    if (steps < 2) return 0;
  }
  // Only the group's fingers move; fingers outside the group cannot be reached (lockstepGroups).
  candidate_ = q_;
  for (Drive* d : members) {
    for (const auto& [joint, amount] : d->moves) candidate_[joint] += steps * amount;
  }
  hand_.normalise(candidate_);
  change_ = candidate_ - q_;
  // Each finger once, though several of its drives may be members.
  const auto firstOfFinger = [&](std::size_t i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (members[k]->finger == members[i]->finger) return false;
    }
    return true;
  };
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (firstOfFinger(i)) noteMove(members[i]->finger, change_);
  }
  q_.swap(candidate_);
  for (std::size_t i = 0; i < members.size(); ++i) {
    Drive* d = members[i];
    if (changes[i].cwiseAbs().maxCoeff() < kNoJointMove) {
      d->stopped = true;  // at its limits, as the stepwise closing's first failed step
    } else {
      d->steps += static_cast<int>(steps);
      d->refused_at.clear();
    }
    if (firstOfFinger(i)) placeFinger(d->finger, q_);
  }
  return static_cast<int>(steps);
}

}  // namespace skelgrasp::grasping::internal
