// Qhull (libqhull_r) is used only in this file.
#include "skelgrasp/grasping/quality/quality.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/pose.h"
#include "skelgrasp/common/resources.h"
#include "skelgrasp/grasping/hand/hand_model.h"

namespace skelgrasp::grasping {

namespace {

// Relative tolerances (dimensionless, scaled by the largest magnitude involved): a tangent
// shorter than this is parallel to the normal; singular values below it do not count to the rank.
constexpr double kRelativeParallelTolerance = 1e-9;
constexpr double kRelativeRankTolerance = 1e-9;
// The contact forces' hull holds the origin strictly when every facet offset is below -this.
constexpr double kForceHullInsideMargin = 1e-9;
// Hull test: closure when every facet is farther than this from the origin (wrench units);
// reference-compatible test: when every facet is within this of containing the origin.
constexpr double kHullClosureMargin = 1e-12;
constexpr double kReferenceHullTolerance = 1e-4;
// Epsilon by expansion stops when its lower and upper bounds are this close (wrench units, the
// order of the joggle Qhull applies; epsilon of closure grasps is 1e-4 to 1).
constexpr double kExpansionTolerance = 1e-12;
}  // namespace

const char* toString(ForceClosureTest test) {
  return test == ForceClosureTest::kHull ? "hull" : "lp";
}

ForceClosureTest parseForceClosureTest(const std::string& text) {
  if (text == "hull") return ForceClosureTest::kHull;
  if (text == "lp") return ForceClosureTest::kLp;
  throw InvalidArgument("unknown force-closure test '" + text + "' (use hull or lp)");
}

std::vector<Eigen::Vector3d> frictionConeEdges(const Eigen::Vector3d& outward_normal,
                                               const QualityParams& params,
                                               const Eigen::Vector3d& reference) {
  const Eigen::Vector3d axis = -outward_normal.normalized();
  Eigen::Vector3d t1 = reference - reference.dot(axis) * axis;
  t1 = t1.norm() > kRelativeParallelTolerance * std::max(1.0, reference.norm())
           ? Eigen::Vector3d(t1.normalized())
           : anyPerpendicular(axis);
  const Eigen::Vector3d t2 = axis.cross(t1);
  // Reference quirk: radial and axial parts both scaled by cos(atan mu) -> 45 degrees.
  const double half_angle = params.reference_compat ? std::atan(1.0) : std::atan(params.friction);
  std::vector<Eigen::Vector3d> edges;
  edges.reserve(params.cone_edges);
  for (int i = 0; i < params.cone_edges; ++i) {
    const double theta = kTwoPi * i / params.cone_edges;
    edges.push_back(std::cos(half_angle) * axis +
                    std::sin(half_angle) * (std::cos(theta) * t1 + std::sin(theta) * t2));
  }
  return edges;
}

std::vector<Wrench> contactWrenches(const std::vector<Contact>& contacts,
                                    const Eigen::Vector3d& center, double torque_scale,
                                    const QualityParams& params) {
  std::vector<Wrench> wrenches;
  // A second reference direction that moves with the grasp, for contacts whose lever arm is along
  // the normal: the normal of the contacts' best-fit plane (its sign does not matter, an even
  // number of edges maps onto itself under a half turn).
  Eigen::Vector3d plane_normal = Eigen::Vector3d::Zero();
  if (contacts.size() >= 3) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& c : contacts) mean += c.point / static_cast<double>(contacts.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto& c : contacts) scatter += (c.point - mean) * (c.point - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    plane_normal = eigen.eigenvectors().col(0);
  }
  // No hand here: the hand's contact model (nullopt) means point contacts.
  const double torsion_m = params.torsional_friction_m.value_or(0.0);
  for (const auto& c : contacts) {
    const Eigen::Vector3d r = c.point - center;
    const Eigen::Vector3d inward = -c.normal.normalized();
    const Eigen::Vector3d tangential = r - r.dot(inward) * inward;
    const Eigen::Vector3d reference =
        tangential.norm() > kRelativeParallelTolerance * std::max(1.0, r.norm()) ? r : plane_normal;
    for (const auto& f : frictionConeEdges(c.normal, params, reference)) {
      Wrench w;
      w << f, torque_scale * r.cross(f);
      if (torsion_m > 0) {
        const Eigen::Vector3d torsion = torque_scale * torsion_m * f.dot(inward) * inward;
        w.tail<3>() += torsion;
        wrenches.push_back(w);
        w.tail<3>() -= 2 * torsion;
      }
      wrenches.push_back(w);
    }
  }
  return wrenches;
}

namespace {

// Calibration of estimateWrenchHullBytes (docs/limits.md, "Grasp quality"): `quality` on 10, 20,
// 40, 80 and 160 random contacts on a sphere x 8 cone edges (80-1280 wrenches) gave 6632, 21190,
// 66835, 208330 and 646139 facets (x 3.1-3.2 per doubling: 4.8 W^1.65), and peak RSS grew by 72
// and 235 MiB for the two largest: 360-380 bytes per facet.
constexpr double kHullFacetsScale = 4.8;
constexpr double kHullFacetsExponent = 1.65;
constexpr double kHullBytesPerFacet = 400;

struct Hull {
  bool ok = false;
  std::vector<std::pair<Eigen::VectorXd, double>>
      facets;  // outward unit normal, offset (n.x + offset = 0)
  double volume = 0;
  Eigen::VectorXd vertex_mean;
  std::string error;
};

// Joggled input (QJ, as the reference) is twice as fast as exact merging (Qt) on 6D wrench sets
// (14 vs 30 ms for 80 wrenches, ~7000 facets) and deterministic; the perturbation (~1e-11
// relative) cannot make a flat set look full-dimensional because the rank is checked exactly first.
template <int Dim>
Hull convexHull(const std::vector<Eigen::Matrix<double, Dim, 1>>& points, bool with_volume) {
  Hull hull;
  hull.vertex_mean = Eigen::VectorXd::Zero(Dim);
  std::vector<coordT> coords;
  coords.reserve(points.size() * Dim);
  for (const auto& p : points) coords.insert(coords.end(), p.data(), p.data() + Dim);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  char* error_text = nullptr;
  std::size_t error_size = 0;
  FILE* errors = open_memstream(&error_text, &error_size);
  qh_zero(qh, errors);
  char options[] = "qhull QJ";
  const int exit_code = qh_new_qhull(qh, Dim, static_cast<int>(points.size()), coords.data(), False,
                                     options, nullptr, errors);
  if (exit_code == 0) {
    hull.ok = true;
    facetT* facet;
    FORALLfacets {
      Eigen::VectorXd normal(Dim);
      for (int k = 0; k < Dim; ++k) normal[k] = facet->normal[k];
      hull.facets.emplace_back(normal, facet->offset);
    }
    if (with_volume) {
      qh_getarea(qh, qh->facet_list);
      hull.volume = qh->totvol;
    }
    vertexT* vertex;
    int count = 0;
    FORALLvertices {
      for (int k = 0; k < Dim; ++k) hull.vertex_mean[k] += vertex->point[k];
      ++count;
    }
    if (count > 0) hull.vertex_mean /= count;
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(errors);
  if (!hull.ok && error_text) hull.error = std::string(error_text, error_size);
  std::free(error_text);
  return hull;
}

// Epsilon without the whole hull: the hull of a growing subset of the wrenches (docs/hands.md,
// "Epsilon by expansion"). The subset's hull lies inside the whole one, so its nearest facet
// bounds epsilon from below; every facet normal's support over all wrenches bounds it from above.
// Each round adds the support points of the facets nearer than that upper bound, as the
// expanding-polytope algorithm does, until the bounds meet. Returns the last subset's hull, whose
// nearest facet is the whole hull's (mustard bottle, Shadow hand: 3.2 hulls of 20 of the 45
// wrenches on average; its planning 1.47 -> 0.82 s with the volume no longer computed).
Hull nearestFacetsHull(const std::vector<Wrench>& wrenches) {
  const std::size_t n = wrenches.size();
  std::vector<char> in_subset(n, 0);
  std::vector<std::size_t> subset;
  const auto add = [&](std::size_t i) {
    if (in_subset[i]) return false;
    in_subset[i] = 1;
    subset.push_back(i);
    return true;
  };
  // Seed: the extreme wrench along each axis, both ways (full-dimensional in practice).
  for (int axis = 0; axis < 6; ++axis) {
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (wrenches[i][axis] < wrenches[lo][axis]) lo = i;
      if (wrenches[i][axis] > wrenches[hi][axis]) hi = i;
    }
    add(lo);
    add(hi);
  }
  while (true) {
    std::vector<Wrench> points;
    points.reserve(subset.size());
    for (std::size_t i : subset) points.push_back(wrenches[i]);
    Hull hull = convexHull<6>(points, false);
    // A flat or too small subset: fall back to every wrench (whose rank was checked).
    if (!hull.ok && subset.size() < n) {
      for (std::size_t i = 0; i < n; ++i) add(i);
      continue;
    }
    if (!hull.ok) return hull;
    double lower = std::numeric_limits<double>::infinity();
    for (const auto& facet : hull.facets) lower = std::min(lower, -facet.second);
    // Per facet, the support of all wrenches along its normal and the wrench attaining it.
    std::vector<std::pair<double, std::size_t>> support(hull.facets.size());
    double upper = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < hull.facets.size(); ++f) {
      support[f] = {-std::numeric_limits<double>::infinity(), 0};
      for (std::size_t i = 0; i < n; ++i) {
        const double reach = hull.facets[f].first.dot(wrenches[i]);
        if (reach > support[f].first) support[f] = {reach, i};
      }
      upper = std::min(upper, support[f].first);
    }
    bool grew = false;
    if (upper - lower > kExpansionTolerance) {
      for (std::size_t f = 0; f < hull.facets.size(); ++f) {
        if (-hull.facets[f].second < upper) grew = add(support[f].second) || grew;
      }
    }
    if (!grew) return hull;
  }
}

// The LP decides; the hull is built only for a closure grasp whose epsilon is wanted. Epsilon is
// clamped at 0: inside the tolerance band the joggled hull may put the origin on a facet.
void decideByLp(const ClosureLpResult& lp, const std::vector<Wrench>& wrenches,
                const QualityParams& params, WrenchSpaceResult& result) {
  const double n = static_cast<double>(wrenches.size());
  result.force_closure = lp.feasible && lp.margin * n > kClosureMarginTolerance;
  result.closure_margin = result.force_closure ? lp.margin : 0.0;
  if (!result.force_closure) {
    result.note = lp.feasible ? "origin on the wrench hull's boundary (LP margin within tolerance)"
                              : "origin outside the wrench hull (LP infeasible)";
    return;
  }
  if (!params.compute_epsilon) return;
  // The volume needs the whole hull; epsilon alone only the facets nearest the origin.
  const Hull hull =
      params.compute_volume ? convexHull<6>(wrenches, true) : nearestFacetsHull(wrenches);
  if (!hull.ok) {
    result.note = "qhull failed: " + hull.error.substr(0, hull.error.find('\n'));
    return;
  }
  result.hull_facets = static_cast<int>(hull.facets.size());
  if (params.compute_volume) result.volume = hull.volume;
  double min_origin = std::numeric_limits<double>::infinity();
  for (const auto& facet : hull.facets) min_origin = std::min(min_origin, -facet.second);
  result.epsilon = std::max(0.0, min_origin);
}

}  // namespace

QualityParams withHandContactModel(QualityParams params, const HandModel& hand) {
  if (!params.torsional_friction_m)
    params.torsional_friction_m = hand.closingDefaults().torsional_friction_m;
  return params;
}

std::size_t wrenchCount(std::size_t contacts, const QualityParams& params) {
  const std::size_t per_edge = params.torsional_friction_m.value_or(0.0) > 0 ? 2 : 1;
  return contacts * static_cast<std::size_t>(std::max(params.cone_edges, 0)) * per_edge;
}

double estimateWrenchHullBytes(std::size_t wrenches) {
  return kHullBytesPerFacet * kHullFacetsScale *
         std::pow(static_cast<double>(wrenches), kHullFacetsExponent);
}

WrenchSpaceResult evaluateWrenchSpace(const std::vector<Contact>& contacts,
                                      const Eigen::Vector3d& center, double torque_scale,
                                      const QualityParams& params) {
  if (!(params.friction >= 0) || params.cone_edges < 3 ||
      !(params.torsional_friction_m.value_or(0.0) >= 0)) {
    throw InvalidArgument(
        "quality: need friction >= 0, torsional friction >= 0 and >= 3 cone edges");
  }
  if (!(torque_scale > 0) || !std::isfinite(torque_scale)) {
    throw InvalidArgument("quality: torque scale must be positive and finite");
  }
  const std::size_t wrench_count = wrenchCount(contacts.size(), params);
  const double hull_bytes = estimateWrenchHullBytes(wrench_count);
  // The message is built only when refusing: grasp planning evaluates thousands of hulls.
  if (!(hull_bytes <= static_cast<double>(memoryLimitBytes()))) {
    checkMemoryEstimate(
        fmt::format("6D wrench hull of {} wrenches ({} contacts x {} cone edges{})", wrench_count,
                    contacts.size(), params.cone_edges,
                    params.torsional_friction_m.value_or(0.0) > 0 ? " x 2 torsion" : ""),
        hull_bytes, "the number of contacts or --cone-edges");
  }
  WrenchSpaceResult result;
  if (params.compute_volume) result.volume = 0.0;  // until a 6D hull gives it
  const bool use_lp = params.fc_test == ForceClosureTest::kLp && !params.reference_compat;
  if (use_lp) result.closure_margin = 0;
  const auto wrenches = contactWrenches(contacts, center, torque_scale, params);
  result.wrenches = static_cast<int>(wrenches.size());
  if (wrenches.size() < 7) {
    result.note = "fewer than 7 wrenches cannot enclose the origin in 6D";
    return result;
  }
  // A hull of wrenches spanning less than 6D has no interior: no force closure (and Qhull would
  // refuse the flat input).
  Eigen::MatrixXd matrix(6, wrenches.size());
  for (std::size_t i = 0; i < wrenches.size(); ++i)
    matrix.col(static_cast<Eigen::Index>(i)) = wrenches[i];
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(matrix);
  const auto& sv = svd.singularValues();
  result.rank =
      static_cast<int>((sv.array() > kRelativeRankTolerance * std::max(1.0, sv[0])).count());
  if (result.rank < 6 && !params.reference_compat) {
    result.note = "wrenches span only " + std::to_string(result.rank) + " dimensions";
    return result;
  }
  if (use_lp) {
    const ClosureLpResult lp = solveClosureLp(wrenches);
    if (lp.error.empty()) {
      decideByLp(lp, wrenches, params, result);
      return result;
    }
    // Never seen in the agreement tests; the hull still gives an answer.
    log().warn("quality: force-closure LP failed ({}), deciding with the hull", lp.error);
    result.closure_margin = std::numeric_limits<double>::quiet_NaN();
    result.note = "LP failed (" + lp.error + "), hull used; ";
  }
  // Necessary condition, 50x cheaper than the 6D hull: the contact forces alone must positively
  // span 3D (origin strictly inside their hull), else some force direction cannot be resisted.
  if (!params.reference_compat) {
    std::vector<Eigen::Vector3d> forces;
    forces.reserve(wrenches.size());
    for (const auto& w : wrenches) forces.push_back(w.head<3>());
    const Hull force_hull = convexHull<3>(forces, false);
    bool inside = force_hull.ok;
    for (const auto& facet : force_hull.facets)
      inside = inside && facet.second < -kForceHullInsideMargin;
    if (!inside) {
      result.note += "contact forces cannot push in every direction";
      return result;
    }
  }
  const Hull hull = convexHull<6>(wrenches, params.compute_volume);
  if (!hull.ok) {
    result.note += "qhull failed: " + hull.error.substr(0, hull.error.find('\n'));
    return result;
  }
  result.hull_facets = static_cast<int>(hull.facets.size());
  if (params.compute_volume) result.volume = hull.volume;
  double min_origin = std::numeric_limits<double>::infinity();
  double min_centre = std::numeric_limits<double>::infinity();
  double max_offset = -std::numeric_limits<double>::infinity();
  for (const auto& [normal, offset] : hull.facets) {
    min_origin = std::min(min_origin, -offset);
    min_centre = std::min(min_centre, -(normal.dot(hull.vertex_mean) + offset));
    max_offset = std::max(max_offset, offset);
  }
  if (params.reference_compat) {
    result.force_closure = max_offset <= kReferenceHullTolerance;
    result.epsilon = result.force_closure ? std::max(0.0, min_centre) : 0.0;
  } else {
    result.force_closure = min_origin > kHullClosureMargin;
    result.epsilon = result.force_closure ? min_origin : 0.0;
  }
  return result;
}

double torqueScaleMaxRadius(const GraspObject& object) {
  return object.maxRadius() > 0 ? 1.0 / object.maxRadius() : 1.0;
}

double torqueScaleLongestSide(const AxisAlignedBox& box) {
  const double longest = box.extent().maxCoeff();
  return longest > 0 ? 2.0 / longest : 1.0;
}

WrenchSpaceResult evaluateGrasp(const std::vector<Contact>& contacts, const GraspObject& object,
                                const QualityParams& params) {
  if (params.reference_compat) {
    return evaluateWrenchSpace(contacts, object.vertexMean(),
                               torqueScaleLongestSide(object.bounds()), params);
  }
  return evaluateWrenchSpace(contacts, object.centerOfMass(), torqueScaleMaxRadius(object), params);
}

}  // namespace skelgrasp::grasping
