// Simulated depth camera: z-buffer rasterisation of triangle meshes through a pinhole model (with
// the shared rasteriser of common/rasterise.h), then the structured-light error model of
// depth_camera.h.
#include "skelgrasp/perception/depth_camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/rasterise.h"

namespace skelgrasp::perception {
namespace {

constexpr double kNearClip = 0.01;  // metres; geometry closer to the camera is clipped away
// The axial noise's grazing term grows without bound towards 90 degrees: the angle is capped this
// far below it (radians).
constexpr double kGrazingCapMarginRad = 1e-3;
// A view direction and `up` whose cross product is shorter than this are parallel (unit vectors).
constexpr double kParallelUpNorm = 1e-9;
// Smallest grazing ramp (radians), so equal start and max angles drop everything past them.
constexpr double kMinGrazingSpanRad = 1e-9;

struct ZBuffer {
  Image<double> depth;
  LabelImage mesh;
  Image<std::int32_t> face;
  std::vector<std::vector<Eigen::Vector3d>> face_normals;  // camera frame, per mesh and face
};

// Keeps the part of a convex polygon with z >= kNearClip.
std::vector<Eigen::Vector3d> clipNear(const std::vector<Eigen::Vector3d>& polygon) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d& b = polygon[(i + 1) % polygon.size()];
    const bool a_in = a.z() >= kNearClip, b_in = b.z() >= kNearClip;
    if (a_in) out.push_back(a);
    if (a_in != b_in) {
      const double t = (kNearClip - a.z()) / (b.z() - a.z());
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

void rasteriseTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                       const Eigen::Vector3d& p2, const PinholeIntrinsics& k, int mesh, int face,
                       ZBuffer& z) {
  const Eigen::Vector3d* p[3] = {&p0, &p1, &p2};
  std::array<Eigen::Vector2d, 3> screen;
  for (int i = 0; i < 3; ++i) {
    const double inv_z = 1.0 / p[i]->z();
    screen[i] = Eigen::Vector2d(k.fx * p[i]->x() * inv_z + k.cx, k.fy * p[i]->y() * inv_z + k.cy);
  }
  raster::rasteriseTriangle(screen, {p0.z(), p1.z(), p2.z()}, k.width, k.height,
                            raster::kCornerSample, [&](int u, int v, double depth) {
                              double& current = z.depth.at(u, v);
                              if (depth < current) {
                                current = depth;
                                z.mesh.at(u, v) = mesh;
                                z.face.at(u, v) = face;
                              }
                            });
}

ZBuffer rasterise(const std::vector<TriangleMesh>& scene, const Pose& camera_to_world,
                  const PinholeIntrinsics& k) {
  ZBuffer z;
  z.depth = Image<double>(k.width, k.height, std::numeric_limits<double>::infinity());
  z.mesh = LabelImage(k.width, k.height, -1);
  z.face = Image<std::int32_t>(k.width, k.height, -1);
  const Pose world_to_camera = camera_to_world.inverse();
  for (std::size_t m = 0; m < scene.size(); ++m) {
    const TriangleMesh& mesh = scene[m];
    std::vector<Eigen::Vector3d> v(mesh.vertices.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = world_to_camera * mesh.vertices[i];
    auto& normals = z.face_normals.emplace_back(mesh.faces.size(), Eigen::Vector3d::Zero());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& t = mesh.faces[f];
      const Eigen::Vector3d &a = v[t[0]], &b = v[t[1]], &c = v[t[2]];
      const Eigen::Vector3d n = (b - a).cross(c - a);
      if (n.norm() > 0) normals[f] = n.normalized();
      const int fi = static_cast<int>(f), mi = static_cast<int>(m);
      if (a.z() >= kNearClip && b.z() >= kNearClip && c.z() >= kNearClip) {
        rasteriseTriangle(a, b, c, k, mi, fi, z);
        continue;
      }
      const auto polygon = clipNear({a, b, c});
      for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
        rasteriseTriangle(polygon[0], polygon[i], polygon[i + 1], k, mi, fi, z);
      }
    }
  }
  return z;
}

double axialSigma(const DepthNoiseParams& n, double z, double theta) {
  const double dz = z - n.axial_sigma_z0_m;
  double sigma = n.axial_sigma_base_m + n.axial_sigma_quadratic * dz * dz;
  const double t = std::min(theta, 0.5 * kPi - kGrazingCapMarginRad);
  sigma += n.axial_sigma_angle / std::sqrt(z) * t * t / ((0.5 * kPi - t) * (0.5 * kPi - t));
  return sigma;
}

void validate(const DepthCameraParams& p) {
  p.intrinsics.validate();
  const auto& n = p.noise;
  if (!(p.min_range_m >= 0) || !(p.max_range_m > p.min_range_m) || n.disparity_step_px < 0 ||
      !(n.baseline_m > 0) || n.grazing_max_rad < n.grazing_start_rad ||
      n.edge_dropout_probability < 0 || n.edge_dropout_probability > 1 ||
      n.random_dropout_probability < 0 || n.random_dropout_probability > 1) {
    throw InvalidArgument("renderDepth: invalid range or noise parameters");
  }
}

}  // namespace

Pose lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  if (!((target - eye).norm() > 0)) throw InvalidArgument("lookAt: eye and target coincide");
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(up);
  if (x.norm() < kParallelUpNorm) x = anyPerpendicular(z);  // looking along `up`
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Pose pose = Pose::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() = eye;
  return pose;
}

std::vector<Pose> orbitPoses(const Eigen::Vector3d& target, double radius, double elevation_rad,
                             int count, double azimuth0_rad) {
  std::vector<Pose> poses;
  for (int i = 0; i < count; ++i) {
    const double azimuth = azimuth0_rad + kTwoPi * i / count;
    const Eigen::Vector3d direction(std::cos(elevation_rad) * std::cos(azimuth),
                                    std::cos(elevation_rad) * std::sin(azimuth),
                                    std::sin(elevation_rad));
    poses.push_back(lookAt(target + radius * direction, target));
  }
  return poses;
}

DepthView renderDepth(const std::vector<TriangleMesh>& scene, const Pose& camera_to_world,
                      const DepthCameraParams& params) {
  validate(params);
  const auto& k = params.intrinsics;
  const auto& noise = params.noise;
  const ZBuffer z = rasterise(scene, camera_to_world, k);

  // What the projector, offset along the camera's x axis, can light.
  ZBuffer projector;
  const bool shadows = noise.enabled && noise.projector_shadow;
  Pose projector_pose = camera_to_world;
  if (shadows) {
    projector_pose.translation() += camera_to_world.linear().col(0) * noise.baseline_m;
    projector = rasterise(scene, projector_pose, k);
  }
  const Pose world_to_projector = projector_pose.inverse();

  std::mt19937_64 rng(noise.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  DepthView view;
  view.depth = DepthImage(k.width, k.height, static_cast<float>(nan));
  view.labels = z.mesh;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const double depth = z.depth.at(u, v);
      if (!std::isfinite(depth)) continue;
      if (!noise.enabled) {
        if (depth >= params.min_range_m && depth <= params.max_range_m) {
          view.depth.at(u, v) = static_cast<float>(depth);
        }
        continue;
      }
      const Eigen::Vector3d ray =
          Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).normalized();
      const Eigen::Vector3d& normal = z.face_normals[z.mesh.at(u, v)][z.face.at(u, v)];
      const double theta = std::acos(std::min(1.0, std::abs(normal.dot(ray))));
      bool drop = false;
      // Draw every random number in a fixed order so the result depends on the seed only.
      const double r_grazing = uniform(rng), r_edge = uniform(rng), r_random = uniform(rng);
      const double r_noise = gaussian(rng);
      if (theta > noise.grazing_start_rad) {
        const double span =
            std::max(kMinGrazingSpanRad, noise.grazing_max_rad - noise.grazing_start_rad);
        drop = drop || r_grazing < (theta - noise.grazing_start_rad) / span;
      }
      bool edge = false;
      const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
      for (int i = 0; i < 4 && !edge; ++i) {
        const int un = u + du[i], vn = v + dv[i];
        if (!z.depth.contains(un, vn)) continue;
        const double other = z.depth.at(un, vn);
        edge = !std::isfinite(other) || other - depth > noise.edge_jump_fraction * depth;
      }
      drop = drop || (edge && r_edge < noise.edge_dropout_probability);
      drop = drop || r_random < noise.random_dropout_probability;
      if (shadows && !drop) {
        const Eigen::Vector3d world = camera_to_world * k.backProject(u, v, depth);
        const Eigen::Vector3d in_projector = world_to_projector * world;
        const int pu =
            static_cast<int>(std::lround(k.fx * in_projector.x() / in_projector.z() + k.cx));
        const int pv =
            static_cast<int>(std::lround(k.fy * in_projector.y() / in_projector.z() + k.cy));
        if (in_projector.z() <= 0 || !projector.depth.contains(pu, pv) ||
            projector.depth.at(pu, pv) < in_projector.z() - 0.02 * in_projector.z()) {
          drop = true;
        }
      }
      if (drop) {
        ++view.dropped_pixels;
        continue;
      }
      double measured = depth + axialSigma(noise, depth, theta) * r_noise;
      if (noise.disparity_step_px > 0 && measured > 0) {
        const double fb = k.fx * noise.baseline_m;
        const double disparity =
            std::round(fb / measured / noise.disparity_step_px) * noise.disparity_step_px;
        measured = disparity > 0 ? fb / disparity : nan;
      }
      if (measured >= params.min_range_m && measured <= params.max_range_m) {
        view.depth.at(u, v) = static_cast<float>(measured);
      }
    }
  }
  view.cloud = depthToPointCloud(view.depth, k, camera_to_world);
  view.point_labels.assign(view.cloud.size(), std::numeric_limits<std::uint32_t>::max());
  for (std::size_t i = 0; i < view.cloud.size(); ++i) {
    if (!view.cloud.points[i].allFinite()) continue;
    ++view.valid_pixels;
    if (view.labels.data[i] >= 0)
      view.point_labels[i] = static_cast<std::uint32_t>(view.labels.data[i]);
  }
  log().debug("depth camera: {} valid pixels, {} dropped by the error model", view.valid_pixels,
              view.dropped_pixels);
  return view;
}

}  // namespace skelgrasp::perception
