// The contact of one link with the object: the exact gap from FCL, the point at the centre of the
// touching patch, or the patch's corners (ContactPatch::kCorners).
#include <algorithm>
#include <cmath>
#include <limits>

#include "simulator_internal.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::grasping::internal {

// Points on a shape's surface in its own frame: box corners, edge midpoints and face centres;
// sphere and cylinder points on their axes and rims; up to 64 mesh vertices.
std::vector<Eigen::Vector3d> surfaceSamples(const CollisionShape& shape) {
  std::vector<Eigen::Vector3d> samples;
  switch (shape.type) {
    case ShapeType::kBox:
      for (int x = -1; x <= 1; ++x) {
        for (int y = -1; y <= 1; ++y) {
          for (int z = -1; z <= 1; ++z) {
            if (x || y || z)
              samples.push_back(0.5 * shape.box_size.cwiseProduct(Eigen::Vector3d(x, y, z)));
          }
        }
      }
      break;
    case ShapeType::kSphere:
      for (int a = 0; a < 3; ++a) {
        for (int sign : {-1, 1}) samples.push_back(sign * shape.radius * Eigen::Vector3d::Unit(a));
      }
      break;
    case ShapeType::kCylinder:
      for (double z : {-0.5, 0.0, 0.5}) {
        if (z != 0.0) samples.emplace_back(0, 0, z * shape.length);
        for (int k = 0; k < 8; ++k) {
          const double a = k * kPi / 4;
          samples.emplace_back(shape.radius * std::cos(a), shape.radius * std::sin(a),
                               z * shape.length);
        }
      }
      break;
    case ShapeType::kMesh: {
      const auto& v = shape.mesh->vertices;
      const std::size_t stride = std::max<std::size_t>(1, v.size() / 64);
      for (std::size_t i = 0; i < v.size(); i += stride) samples.push_back(v[i]);
      break;
    }
  }
  return samples;
}

double boundingRadius(const CollisionShape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      return 0.5 * shape.box_size.norm();
    case ShapeType::kSphere:
      return shape.radius;
    case ShapeType::kCylinder:
      return std::hypot(shape.radius, 0.5 * shape.length);
    case ShapeType::kMesh: {
      double r = 0;
      for (const auto& v : shape.mesh->vertices) r = std::max(r, v.norm());
      return r;
    }
  }
  return std::numeric_limits<double>::infinity();
}

std::vector<std::pair<Eigen::Vector3d, double>> sphereCover(const CollisionShape& shape) {
  // Boxes and cylinders are cut along their longest extent into pieces about as long as they are
  // wide, each covered by its bounding sphere.
  const auto along = [](const Eigen::Vector3d& half, int axis) {
    Eigen::Vector3d cross = half;
    cross[axis] = 0;
    const double length = 2 * half[axis], width = std::max(2 * cross.maxCoeff(), 1e-6);
    const int pieces = std::clamp(static_cast<int>(std::ceil(length / width)), 1, 8);
    std::vector<std::pair<Eigen::Vector3d, double>> cover;
    Eigen::Vector3d piece_half = half;
    piece_half[axis] = half[axis] / pieces;
    for (int k = 0; k < pieces; ++k) {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      centre[axis] = -half[axis] + (2 * k + 1) * piece_half[axis];
      cover.emplace_back(centre, piece_half.norm());
    }
    return cover;
  };
  switch (shape.type) {
    case ShapeType::kBox: {
      const Eigen::Vector3d half = 0.5 * shape.box_size;
      int axis = 0;
      half.maxCoeff(&axis);
      return along(half, axis);
    }
    case ShapeType::kCylinder: {
      // The square around the disc holds the cylinder.
      return along(Eigen::Vector3d(shape.radius, shape.radius, 0.5 * shape.length), 2);
    }
    case ShapeType::kSphere:
      return {{Eigen::Vector3d::Zero(), shape.radius}};
    case ShapeType::kMesh:
      return {{Eigen::Vector3d::Zero(), boundingRadius(shape)}};
  }
  return {};
}

namespace {

// The exact distance between a link and the object with the nearest points, from FCL.
struct FclGap {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d object_point = Eigen::Vector3d::Zero(), link_point = Eigen::Vector3d::Zero();
};

FclGap fclGap(const std::vector<ShapeInstance>& shapes, const GraspObject& object,
              std::size_t& queries) {
  const auto& fcl_object = object.collisionData().distanceObject();
  fcl::DistanceRequestd request(true);
  FclGap gap;
  for (const auto& s : shapes) {
    fcl::DistanceResultd distance;
    ++queries;
    // The object goes first: FCL 0.7 reports mesh-shape pairs with the mesh as object 1 (b1,
    // nearest_points[0]) whatever the argument order.
    fcl::distance(&fcl_object, s.object.get(), request, distance);
    if (distance.min_distance < gap.distance) {
      gap.distance = distance.min_distance;
      gap.object_point = distance.nearest_points[0];
      gap.link_point = distance.nearest_points[1];
    }
  }
  return gap;
}

Contact makeContact(const HandModel& hand, int link, const GraspObject& object,
                    const Eigen::Vector3d& point, std::size_t face,
                    const Eigen::Vector3d& link_centre, bool palm, double gap) {
  Contact contact;
  contact.point = point;
  contact.normal = object.surfaceNormal(point, face, link_centre - point);
  contact.link = hand.links()[link].name;
  contact.palm = palm;
  contact.distance = gap;
  return contact;
}

// A patch point: the object's closest point to a link surface sample, the sample, and the centre
// of the sample's shape (inside the link: it tells the outward normal where the sample touches).
struct PatchPoint {
  SurfacePoint on_surface;
  Eigen::Vector3d on_link;
  Eigen::Vector3d shape_centre;
};

// A link sample this close to the surface (m) is on it.
constexpr double kOnSurfaceM = 1e-9;

// Where one contact at the patch's centre sits: the mean of the patch's object points, and the
// mean of the link samples that found them (the side the link is on). `patch` is not empty.
struct PatchCentre {
  Eigen::Vector3d on_surface = Eigen::Vector3d::Zero();
  Eigen::Vector3d on_link = Eigen::Vector3d::Zero();
};
PatchCentre patchCentre(const std::vector<PatchPoint>& patch) {
  PatchCentre centre;
  for (const auto& p : patch) {
    centre.on_surface += p.on_surface.point;
    centre.on_link += p.on_link;
  }
  centre.on_surface /= static_cast<double>(patch.size());
  centre.on_link /= static_cast<double>(patch.size());
  return centre;
}

// The corners of an extended patch (a phalanx lying on a face or along an edge) as contacts: the
// two points farthest apart, and on either side of the line through them the point farthest from
// it when that is kMinCornerPatchSpanM away. Rigid bodies touching over an area push through the
// area's corners (the polyhedral model of a face contact); the patch's centre alone holds no
// moment about itself. Empty when the patch spans less than kMinCornerPatchSpanM (one contact
// then).
std::vector<Contact> patchCornerContacts(const HandModel& hand, int link, const GraspObject& object,
                                         const std::vector<PatchPoint>& patch,
                                         const Eigen::Vector3d& centre, bool palm, double gap) {
  if (patch.size() < 2) return {};
  const auto farthestFrom = [&](const Eigen::Vector3d& from) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < patch.size(); ++i) {
      if ((patch[i].on_surface.point - from).squaredNorm() >
          (patch[best].on_surface.point - from).squaredNorm())
        best = i;
    }
    return best;
  };
  const std::size_t a = farthestFrom(centre);
  const std::size_t b = farthestFrom(patch[a].on_surface.point);
  const Eigen::Vector3d pa = patch[a].on_surface.point, pb = patch[b].on_surface.point;
  if ((pb - pa).norm() < kMinCornerPatchSpanM) return {};
  std::vector<std::size_t> corners = {a, b};
  // Offsets from the line ab: the point farthest from it, then the farthest on the other side.
  const Eigen::Vector3d axis = (pb - pa).normalized();
  std::vector<Eigen::Vector3d> offsets;
  for (const auto& p : patch) {
    const Eigen::Vector3d off = p.on_surface.point - pa;
    offsets.push_back(off - off.dot(axis) * axis);
  }
  const auto farthestAlong = [&](const auto& reach) -> std::optional<std::size_t> {
    std::optional<std::size_t> best;
    double best_reach = kMinCornerPatchSpanM;
    for (std::size_t i = 0; i < patch.size(); ++i) {
      if (reach(offsets[i]) >= best_reach) {
        best_reach = reach(offsets[i]);
        best = i;
      }
    }
    return best;
  };
  if (const auto side = farthestAlong([](const Eigen::Vector3d& off) { return off.norm(); })) {
    corners.push_back(*side);
    const Eigen::Vector3d away = -offsets[*side].normalized();
    if (const auto other = farthestAlong([&](const Eigen::Vector3d& off) { return off.dot(away); }))
      corners.push_back(*other);
  }
  std::vector<Contact> contacts;
  for (std::size_t i : corners) {
    const auto& p = patch[i];
    const double distance = (p.on_link - p.on_surface.point).norm();
    // The sample's side of the surface says the normal, as the centre's does; a sample on the
    // surface says nothing, its shape's centre does.
    const Eigen::Vector3d& outside = distance > kOnSurfaceM ? p.on_link : p.shape_centre;
    contacts.push_back(makeContact(hand, link, object, p.on_surface.point, p.on_surface.face,
                                   outside, palm, std::max(gap, distance)));
  }
  return contacts;
}

std::vector<Contact> stepwiseContactPatch(const HandModel& hand,
                                          const std::vector<ShapeInstance>& shapes, int link,
                                          const Pose& link_pose, const GraspObject& object,
                                          bool palm, double max_distance, bool corner_contacts,
                                          std::size_t& queries) {
  const auto& surface = object.surfaceQuery();
  // A link whose bounding spheres all stay farther than max_distance from the surface cannot be
  // in contact: one closest-point query instead of an exact FCL distance, which dominated closing.
  bool near = false;
  for (const auto& s : shapes) {
    const Eigen::Vector3d centre = link_pose * s.origin.translation();
    near = near || surface.distance(centre) <= s.bounding_radius + max_distance;
  }
  if (!near) return {};
  // FCL gives the exact gap but an arbitrary point of a flat contact patch (a pad on a face), so
  // the point is the centre of the patch: the object points closest to the link's surface samples
  // that lie within kContactPatchBandM of the gap.
  const FclGap exact = fclGap(shapes, object, queries);
  if (exact.distance > max_distance) return {};
  const double gap = std::max(0.0, exact.distance);
  // FCL's point is only a fallback: on a flat patch it is any point, and it would bias the mean.
  std::vector<PatchPoint> patch;
  for (const auto& s : shapes) {
    const Pose shape_pose = link_pose * s.origin;
    for (const auto& sample : s.surface_samples) {
      const Eigen::Vector3d p = shape_pose * sample;
      const auto [closest, face] = surface.closestPointAndFace(p);
      const double distance = (p - closest).norm();
      if (distance <= gap + kContactPatchBandM)
        patch.push_back({SurfacePoint{closest, face, distance}, p, shape_pose.translation()});
    }
  }
  const PatchCentre centre =
      patch.empty() ? PatchCentre{exact.object_point, exact.link_point} : patchCentre(patch);
  if (corner_contacts) {
    std::vector<Contact> corners =
        patchCornerContacts(hand, link, object, patch, centre.on_surface, palm, gap);
    if (!corners.empty()) return corners;
  }
  const auto [point, face] = surface.closestPointAndFace(centre.on_surface);
  return {makeContact(hand, link, object, point, face, centre.on_link, palm, gap)};
}

// Over a few field cells the exact closest-point query scans too many triangles: CGAL's tree.
constexpr double kExactClosestReachM = 0.008;

// The same gap, patch and contact as stepwiseContactPatch, from the object's distance field:
// field bounds skip what is far, the triangle grid gives exact box gaps and closest points near
// the surface, and FCL only runs for links that are not boxes.
std::vector<Contact> fastContactPatch(const HandModel& hand,
                                      const std::vector<ShapeInstance>& shapes, int link,
                                      const Pose& link_pose, const GraspObject& object, bool palm,
                                      double max_distance, bool corner_contacts, bool gap_hints,
                                      std::size_t& queries) {
  const DistanceField& field = object.distanceField();
  if (shapes.empty()) return {};  // nothing of the link can touch
  // The shapes' sphere bounds (a field lookup per sphere) reject a far link before any exact gap.
  std::vector<double> sphere_bounds;
  sphere_bounds.reserve(shapes.size());
  for (const auto& s : shapes) sphere_bounds.push_back(sphereCoverLowerBound(s, field));
  if (*std::min_element(sphere_bounds.begin(), sphere_bounds.end()) > max_distance) return {};
  // Gaps at or beyond `upper` come back as `upper`.
  const double upper = max_distance + kContactPatchBandM;
  // One box per shape: a box shape itself (its exact gap), or the box that holds a cylinder or a
  // sphere (a lower bound of its gap). Gaps at or beyond `best` come back as `best`. Each box is
  // searched once, and the face its gap was found at gives the closest points if the patch needs
  // them (a box edge touching).
  bool all_boxes = true, all_held = true;
  double best = upper;
  const ShapeInstance* closest_box = nullptr;  // used only when every shape is a box
  std::optional<std::size_t> closest_face;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const ShapeInstance& s = shapes[i];
    all_boxes = all_boxes && s.is_box;
    if (!s.enclosing_half) {
      all_held = false;
      continue;
    }
    // A box's spheres cover it, so a sphere bound at or beyond `best` means its gap would come
    // back as `best`: no search. (A sphere's enclosing box sticks out of its one sphere.)
    if (s.is_box && sphere_bounds[i] >= best) continue;
    const DistanceField::BoxGap gap = shapeBoxGap(s, field, best, gap_hints);
    if (gap.distance < best) {
      best = gap.distance;
      closest_box = &s;
      closest_face = gap.face;
    }
  }
  // Every box gap (or bound) and every other shape's sphere bound beyond max_distance: no contact.
  double link_bound = best;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (!shapes[i].enclosing_half) link_bound = std::min(link_bound, sphere_bounds[i]);
  }
  if (link_bound > max_distance) return {};
  // Every shape provably farther than max_distance: no contact and no FCL query (the SDH's palm
  // and knuckle cylinders had taken a third of a settled score in those).
  if (all_held && best >= upper) return {};
  std::optional<FclGap> exact;
  if (!all_boxes || best >= upper) {
    exact = fclGap(shapes, object, queries);
    best = exact->distance;
  }
  if (best > max_distance) return {};
  const double gap = std::max(0.0, best);
  const double band = gap + kContactPatchBandM;
  std::vector<PatchPoint> patch;
  for (const auto& s : shapes) {
    const Pose shape_pose = link_pose * s.origin;
    for (const auto& sample : s.surface_samples) {
      const Eigen::Vector3d p = shape_pose * sample;
      if (field.lowerBound(p) > band) continue;
      const auto closest = field.closestPointWithin(p, band);
      if (closest) patch.push_back({*closest, p, shape_pose.translation()});
    }
  }
  PatchCentre centre;
  // A patch point bounds the distance of the patch centre from the surface.
  double reach = std::numeric_limits<double>::infinity();
  if (patch.empty()) {
    // No surface sample near the gap (a box edge or corner touches): the closest points of the
    // box and its nearest triangle, which FCL would find by GJK over the whole mesh.
    std::optional<DistanceField::BoxClosestPoints> pair;
    if (!exact && closest_box && closest_face && best > 0) {
      pair = field.boxClosestPointsOnFace(shapePose(*closest_box), *closest_box->enclosing_half,
                                          *closest_face);
    }
    if (pair) {
      centre = {pair->on_surface.point, pair->on_box};
    } else {
      if (!exact) exact = fclGap(shapes, object, queries);
      centre = {exact->object_point, exact->link_point};
    }
    reach = 0;
  } else {
    centre = patchCentre(patch);
    if (corner_contacts) {
      std::vector<Contact> corners =
          patchCornerContacts(hand, link, object, patch, centre.on_surface, palm, gap);
      if (!corners.empty()) return corners;
    }
    for (const auto& q : patch)
      reach = std::min(reach, (centre.on_surface - q.on_surface.point).norm());
  }
  reach = std::min(reach, field.unsignedUpperBound(centre.on_surface));
  std::optional<SurfacePoint> nearest;
  if (reach <= kExactClosestReachM)
    nearest = field.closestPointWithin(centre.on_surface, reach + 1e-12);
  if (!nearest) {
    const auto [point, face] = object.surfaceQuery().closestPointAndFace(centre.on_surface);
    nearest = SurfacePoint{point, face, 0};
  }
  return {
      makeContact(hand, link, object, nearest->point, nearest->face, centre.on_link, palm, gap)};
}

}  // namespace

std::vector<Contact> contactPatch(const HandModel& hand, const std::vector<ShapeInstance>& shapes,
                                  int link, const Pose& link_pose, const GraspObject& object,
                                  bool palm, double max_distance, ClosingMethod method,
                                  bool corner_contacts, bool gap_hints, std::size_t& queries) {
  SKELGRASP_DEMAND(std::isfinite(max_distance) && max_distance >= 0);
  if (method == ClosingMethod::kFast) {
    return fastContactPatch(hand, shapes, link, link_pose, object, palm, max_distance,
                            corner_contacts, gap_hints, queries);
  }
  return stepwiseContactPatch(hand, shapes, link, link_pose, object, palm, max_distance,
                              corner_contacts, queries);
}

}  // namespace skelgrasp::grasping::internal
