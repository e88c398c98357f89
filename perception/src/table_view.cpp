// One object on a table seen by the simulated depth camera from seeded single viewpoints
// (table_view.h).
#include "skelgrasp/perception/table_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/geometry/principal_axes.h"
#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::perception {
namespace {

// A mesh whose |signed volume| is below this (m^3) has no usable volume: its centre of mass is
// taken on the surface.
constexpr double kMinVolumeM3 = 1e-12;
// Table mesh subdivisions per side: enough cells that the rasteriser's depth interpolation over
// the table is exact (a plane interpolates exactly anyway; a few cells keep triangles small).
constexpr int kTableSubdivisions = 4;
// Noise seeds of the views: seed * kSeedStride + view + 1, so neighbouring seeds give disjoint
// noise for up to kSeedStride views.
constexpr std::uint64_t kSeedStride = 1000;

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain: the convex hull, counter-clockwise, without collinear points.
std::vector<Eigen::Vector2d> convexHull2(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Whether `p` lies inside the counter-clockwise convex polygon (a polygon of fewer than three
// points holds nothing: an object on an edge or a point is not at rest).
bool insideConvex(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  if (hull.size() < 3) return false;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    if (cross2(hull[i], hull[(i + 1) % hull.size()], p) < 0) return false;
  }
  return true;
}

struct Support {
  bool stable = false;
  double com_height = 0;  // centre of mass above the support plane
};

// The object resting with `down` (unit, mesh frame) towards the table.
Support supportAlong(const TriangleMesh& mesh, const Eigen::Vector3d& down,
                     const Eigen::Vector3d& com, double tolerance) {
  double lowest = -std::numeric_limits<double>::infinity();
  for (const auto& v : mesh.vertices) lowest = std::max(lowest, down.dot(v));
  const Eigen::Vector3d u = anyPerpendicular(down).normalized();
  const Eigen::Vector3d w = down.cross(u);
  std::vector<Eigen::Vector2d> contact;
  for (const auto& v : mesh.vertices) {
    if (down.dot(v) >= lowest - tolerance) contact.emplace_back(u.dot(v), w.dot(v));
  }
  Support s;
  s.com_height = lowest - down.dot(com);
  s.stable = insideConvex(convexHull2(std::move(contact)), {u.dot(com), w.dot(com)});
  return s;
}

void check(bool ok, const char* what) {
  if (!ok) throw InvalidArgument(std::string("table views: ") + what);
}

}  // namespace

void TableViewParams::validate() const {
  check(views >= 1, "at least one view");
  check(min_distance_m > 0 && max_distance_m >= min_distance_m && std::isfinite(max_distance_m),
        "the camera distance range must be positive and ordered");
  check(min_elevation_rad > 0 && max_elevation_rad >= min_elevation_rad &&
            max_elevation_rad < 0.5 * kPi,
        "the elevation range must lie in (0, 90) degrees and be ordered");
  check(table_length_m > 0 && table_width_m > 0 && table_thickness_m > 0,
        "the table needs a positive size");
  check(noise_scale >= 0 && std::isfinite(noise_scale), "the noise scale must be >= 0");
  check(support_tolerance_m >= 0, "the support tolerance must be >= 0");
}

Eigen::Vector3d centreOfMass(const TriangleMesh& mesh) {
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  double volume = 0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]],
                          &c = mesh.vertices[f[2]];
    const double v = a.dot(b.cross(c)) / 6.0;  // tetrahedron with the origin
    volume += v;
    moment += v * (a + b + c) / 4.0;
  }
  if (std::abs(volume) > kMinVolumeM3) return moment / volume;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double area = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const double a = mesh.faceArea(f);
    const auto& t = mesh.faces[f];
    centroid += a * (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
    area += a;
  }
  if (area > 0) return centroid / area;
  return mesh.bounds().center();
}

RestingPose restingPose(const TriangleMesh& object, const TableViewParams& params) {
  params.validate();
  if (object.vertices.empty()) throw InvalidArgument("table views: empty mesh");
  const Eigen::Vector3d com = centreOfMass(object);
  RestingPose rest;
  const Eigen::Vector3d own = -Eigen::Vector3d::UnitZ();
  if (supportAlong(object, own, com, params.support_tolerance_m).stable) {
    rest.down_in_object = own;
  } else {
    rest.own_orientation = false;
    rest.stable = false;
    const auto axes = geometry::surfacePrincipalAxes(object);
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      for (const double sign : {1.0, -1.0}) {
        const Eigen::Vector3d down = sign * axes.axes.col(a).normalized();
        const Support s = supportAlong(object, down, com, params.support_tolerance_m);
        if (s.stable && s.com_height < best) {
          best = s.com_height;
          rest.down_in_object = down;
          rest.stable = true;
        }
      }
    }
    if (!rest.stable) rest.down_in_object = own;
  }
  // Seeded yaw: the same object is seen turned differently for different seeds.
  std::mt19937_64 rng(params.seed);
  std::uniform_real_distribution<double> turn(0.0, kTwoPi);
  rest.yaw_rad = turn(rng);
  const Eigen::Matrix3d tilt =
      Eigen::Quaterniond::FromTwoVectors(rest.down_in_object, -Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(rest.yaw_rad, Eigen::Vector3d::UnitZ()) * tilt;
  TriangleMesh turned = object;
  turned.transform(pose);
  const AxisAlignedBox box = turned.bounds();
  pose.pretranslate(Eigen::Vector3d(-box.center().x(), -box.center().y(), -box.min.z()));
  rest.world_from_object = pose;
  rest.centre_of_mass_world = pose * com;
  return rest;
}

TableViews renderTableViews(const TriangleMesh& object, const TableViewParams& params) {
  params.validate();
  TableViews out;
  if (object.vertices.empty() || object.faces.empty()) {
    out.status = Status::Make(StatusCode::kInvalidInput, "the mesh has no faces");
    return out;
  }
  out.rest = restingPose(object, params);
  out.object = object;
  out.object.transform(out.rest.world_from_object);
  out.table = geometry::shapes::makeBox(
      {params.table_length_m, params.table_width_m, params.table_thickness_m}, kTableSubdivisions);
  out.table.transform(Pose(Eigen::Translation3d(0, 0, -0.5 * params.table_thickness_m)));
  const std::vector<TriangleMesh> scene = {out.table, out.object};
  const Eigen::Vector3d target = out.object.bounds().center();

  // The viewpoints: one generator, drawn in a fixed order (after the resting pose's yaw).
  std::mt19937_64 rng(params.seed ^ 0x5ca9u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double azimuth0 = kTwoPi * unit(rng);
  for (int v = 0; v < params.views; ++v) {
    TableView view;
    view.azimuth_rad = azimuth0 + kTwoPi * v / params.views;
    view.distance_m =
        params.min_distance_m + (params.max_distance_m - params.min_distance_m) * unit(rng);
    view.elevation_rad = params.min_elevation_rad +
                         (params.max_elevation_rad - params.min_elevation_rad) * unit(rng);
    const Eigen::Vector3d direction(std::cos(view.elevation_rad) * std::cos(view.azimuth_rad),
                                    std::cos(view.elevation_rad) * std::sin(view.azimuth_rad),
                                    std::sin(view.elevation_rad));
    view.world_from_camera = lookAt(target + view.distance_m * direction, target);
    DepthCameraParams camera = params.camera;
    view.noise_seed = params.seed * kSeedStride + static_cast<std::uint64_t>(v) + 1;
    camera.noise.seed = view.noise_seed;
    camera.noise.axial_sigma_base_m *= params.noise_scale;
    camera.noise.axial_sigma_quadratic *= params.noise_scale;
    camera.noise.axial_sigma_angle *= params.noise_scale;
    const DepthView depth = renderDepth(scene, view.world_from_camera, camera);
    view.dropped_pixels = depth.dropped_pixels;
    for (std::size_t i = 0; i < depth.cloud.size(); ++i) {
      if (!depth.cloud.points[i].allFinite()) continue;
      (depth.point_labels[i] == 1 ? view.object_pixels : view.table_pixels) += 1;
    }
    // The camera's own frame: what a real sensor delivers.
    const Pose camera_from_world = view.world_from_camera.inverse();
    view.scan.cloud = depth.cloud;
    for (auto& p : view.scan.cloud.points) {
      if (p.allFinite()) p = camera_from_world * p;
    }
    view.scan.cloud.sensor_origin = Eigen::Vector3d::Zero();
    view.scan.cloud.sensor_orientation = Eigen::Quaterniond::Identity();
    view.scan.views = 1;
    view.scan.source = "table view " + std::to_string(v);
    view.object_from_scan = out.rest.world_from_object.inverse() * view.world_from_camera;
    if (view.object_pixels == 0 && out.status.ok()) {
      out.status = Status::Make(StatusCode::kNoResult,
                                "view " + std::to_string(v) + " sees no pixel of the object");
    }
    out.views.push_back(std::move(view));
  }
  return out;
}

}  // namespace skelgrasp::perception
