#include "skelgrasp/geometry/shapes.h"

#include <cmath>

#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::geometry::shapes {
namespace {

// Vertices closer than this are one vertex when the box's sides are welded (metres; the sides'
// shared edge vertices are computed identically, so they coincide up to rounding).
constexpr double kWeldDistanceM = 1e-12;

int addVertex(TriangleMesh& mesh, const Eigen::Vector3d& p) {
  mesh.vertices.push_back(p);
  return static_cast<int>(mesh.vertices.size()) - 1;
}

// Quad (a, b, c, d) counter-clockwise seen from outside.
void addQuad(TriangleMesh& mesh, int a, int b, int c, int d) {
  mesh.faces.emplace_back(a, b, c);
  mesh.faces.emplace_back(a, c, d);
}

Eigen::Isometry3d placement(const Eigen::Vector3d& translation,
                            const Eigen::AngleAxisd& rotation = Eigen::AngleAxisd::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation.toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

TriangleMesh placed(TriangleMesh mesh, const Eigen::Isometry3d& pose) {
  mesh.transform(pose);
  return mesh;
}

}  // namespace

TriangleMesh makeBox(const Eigen::Vector3d& size, int subdivisions) {
  if ((size.array() <= 0).any() || subdivisions < 1) {
    throw InvalidArgument("makeBox: sizes must be positive and subdivisions >= 1");
  }
  TriangleMesh mesh;
  const int n = subdivisions;
  // Each face: origin corner, two edge directions (u x v points outward).
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {-1, 1}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[axis] = sign;
      Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = 1;
      if (sign < 0) std::swap(u, v);
      const Eigen::Vector3d half = 0.5 * size;
      const Eigen::Vector3d center = normal.cwiseProduct(half);
      const Eigen::Vector3d du = u.cwiseProduct(size), dv = v.cwiseProduct(size);
      const int base = static_cast<int>(mesh.vertices.size());
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          addVertex(mesh, center + (i / double(n) - 0.5) * du + (j / double(n) - 0.5) * dv);
        }
      }
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const int a = base + i * (n + 1) + j;
          addQuad(mesh, a, a + (n + 1), a + (n + 1) + 1, a + 1);
        }
      }
    }
  }
  // Faces built per side share no vertices; weld the duplicated edge vertices.
  std::vector<int> remap(mesh.vertices.size());
  std::vector<Eigen::Vector3d> unique;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    int found = -1;
    for (std::size_t k = 0; k < unique.size(); ++k) {
      if ((unique[k] - mesh.vertices[i]).norm() < kWeldDistanceM) {
        found = static_cast<int>(k);
        break;
      }
    }
    if (found < 0) {
      unique.push_back(mesh.vertices[i]);
      found = static_cast<int>(unique.size()) - 1;
    }
    remap[i] = found;
  }
  mesh.vertices = unique;
  for (auto& f : mesh.faces) f = Eigen::Vector3i(remap[f[0]], remap[f[1]], remap[f[2]]);
  return mesh;
}

TriangleMesh makeRevolution(const std::vector<Eigen::Vector2d>& profile, int segments) {
  if (profile.size() < 2 || segments < 3) {
    throw InvalidArgument("makeRevolution: need >= 2 profile points and >= 3 segments");
  }
  TriangleMesh mesh;
  std::vector<int> ring_start(profile.size(), -1);  // -1: pole
  std::vector<int> pole(profile.size(), -1);
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const double r = profile[i].x(), z = profile[i].y();
    if (r <= 0) {
      pole[i] = addVertex(mesh, {0, 0, z});
      continue;
    }
    ring_start[i] = static_cast<int>(mesh.vertices.size());
    for (int s = 0; s < segments; ++s) {
      const double a = kTwoPi * s / segments;
      addVertex(mesh, {r * std::cos(a), r * std::sin(a), z});
    }
  }
  auto ring = [&](std::size_t i, int s) { return ring_start[i] + (s % segments); };
  for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
    for (int s = 0; s < segments; ++s) {
      if (pole[i] >= 0 && pole[i + 1] < 0) {
        mesh.faces.emplace_back(pole[i], ring(i + 1, s + 1), ring(i + 1, s));
      } else if (pole[i] < 0 && pole[i + 1] >= 0) {
        mesh.faces.emplace_back(ring(i, s), ring(i, s + 1), pole[i + 1]);
      } else if (pole[i] < 0 && pole[i + 1] < 0) {
        addQuad(mesh, ring(i, s), ring(i, s + 1), ring(i + 1, s + 1), ring(i + 1, s));
      }
    }
  }
  // Flat caps where an end of the profile has a non-zero radius.
  if (pole.front() < 0) {
    const int c = addVertex(mesh, {0, 0, profile.front().y()});
    for (int s = 0; s < segments; ++s) mesh.faces.emplace_back(c, ring(0, s + 1), ring(0, s));
  }
  if (pole.back() < 0) {
    const std::size_t last = profile.size() - 1;
    const int c = addVertex(mesh, {0, 0, profile.back().y()});
    for (int s = 0; s < segments; ++s) mesh.faces.emplace_back(c, ring(last, s), ring(last, s + 1));
  }
  return mesh;
}

TriangleMesh makeSphere(double radius, int segments, int rings) {
  std::vector<Eigen::Vector2d> profile;
  for (int i = 0; i <= rings; ++i) {
    const double theta = kPi * i / rings;  // from the south pole
    profile.emplace_back(i == 0 || i == rings ? 0.0 : radius * std::sin(theta),
                         -radius * std::cos(theta));
  }
  return makeRevolution(profile, segments);
}

TriangleMesh makeCylinder(double radius, double height, int segments, int rings) {
  std::vector<Eigen::Vector2d> profile;
  for (int i = 0; i <= rings; ++i) profile.emplace_back(radius, -height / 2 + height * i / rings);
  return makeRevolution(profile, segments);
}

TriangleMesh makeFrustum(double r_bottom, double r_top, double height, int segments) {
  return makeRevolution({{r_bottom, 0.0}, {r_top, height}}, segments);
}

TriangleMesh makeCapsule(double radius, double cylinder_length, int segments) {
  std::vector<Eigen::Vector2d> profile;
  const int cap_rings = std::max(4, segments / 4);
  const double half = cylinder_length / 2;
  for (int i = 0; i <= cap_rings; ++i) {
    const double t = 0.5 * kPi * i / cap_rings;
    profile.emplace_back(i == 0 ? 0.0 : radius * std::sin(t), -half - radius * std::cos(t));
  }
  const int body_rings = std::max(1, static_cast<int>(std::ceil(cylinder_length / (radius * 0.5))));
  for (int i = 1; i < body_rings; ++i) {
    profile.emplace_back(radius, -half + cylinder_length * i / body_rings);
  }
  for (int i = cap_rings; i >= 0; --i) {
    const double t = 0.5 * kPi * i / cap_rings;
    profile.emplace_back(i == 0 ? 0.0 : radius * std::sin(t), half + radius * std::cos(t));
  }
  return makeRevolution(profile, segments);
}

TriangleMesh makeTorus(double major_radius, double minor_radius, int major_segments,
                       int minor_segments) {
  if (minor_radius <= 0 || major_radius <= minor_radius) {
    throw InvalidArgument("makeTorus: need 0 < minor_radius < major_radius");
  }
  TriangleMesh mesh;
  for (int i = 0; i < major_segments; ++i) {
    const double u = kTwoPi * i / major_segments;
    for (int j = 0; j < minor_segments; ++j) {
      const double v = kTwoPi * j / minor_segments;
      const double r = major_radius + minor_radius * std::cos(v);
      addVertex(mesh, {r * std::cos(u), r * std::sin(u), minor_radius * std::sin(v)});
    }
  }
  auto idx = [&](int i, int j) {
    return (i % major_segments) * minor_segments + (j % minor_segments);
  };
  for (int i = 0; i < major_segments; ++i) {
    for (int j = 0; j < minor_segments; ++j) {
      addQuad(mesh, idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
    }
  }
  return mesh;
}

std::vector<std::string> namedShapes() {
  return {"capsule", "y_shape", "t_shape", "torus", "mug",
          "bottle",  "box",     "hammer",  "ball",  "rod"};
}

TriangleMesh makeNamedShape(const std::string& name) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  const Vector3d x = Vector3d::UnitX();
  if (name == "capsule") return makeCapsule(0.025, 0.12);
  if (name == "rod") return makeCapsule(0.005, 0.16, 16);
  if (name == "ball") return makeSphere(0.035);
  if (name == "box") return makeBox({0.06, 0.09, 0.16}, 4);
  if (name == "torus") return makeTorus(0.06, 0.015);
  if (name == "y_shape" || name == "t_shape") {
    // Three arms of radius 2 cm meeting at the origin: at 120 degrees (Y) or as a T.
    const double arm = 0.09, r = 0.02;
    const std::vector<double> angles =
        name == "y_shape" ? std::vector<double>{90, 210, 330} : std::vector<double>{0, 180, 270};
    TriangleMesh mesh;
    for (double deg : angles) {
      const double a = radiansFromDegrees(deg);
      const Vector3d dir(std::cos(a), std::sin(a), 0);
      // The cylinder's z axis is turned onto dir; its centre sits half an arm out.
      const auto rot = Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), dir);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = rot.toRotationMatrix();
      pose.translation() = dir * (arm / 2);
      mesh.append(placed(makeCylinder(r, arm, 32, 12), pose));
    }
    mesh.append(makeSphere(r));
    return mesh;
  }
  if (name == "mug") {
    // Solid body 6 cm wide and 12 cm tall with a ring handle in the xz plane on the +x side. The
    // body extends beyond the handle, so its skeleton is the handle loop plus two body arms.
    TriangleMesh mesh = makeCylinder(0.03, 0.12, 48, 10);
    mesh.append(
        placed(makeTorus(0.025, 0.007), placement({0.03 + 0.008, 0, 0}, AngleAxisd(kPi / 2, x))));
    return mesh;
  }
  if (name == "bottle") {
    // Body, shoulder and neck along z, standing on z = 0.
    return makeRevolution({{0.0, 0.0},
                           {0.035, 0.0},
                           {0.035, 0.06},
                           {0.035, 0.13},
                           {0.03, 0.15},
                           {0.014, 0.175},
                           {0.013, 0.21},
                           {0.013, 0.23},
                           {0.0, 0.23}},
                          40);
  }
  if (name == "hammer") {
    // Handle along z with a box head across the top: a T.
    TriangleMesh mesh = placed(makeCylinder(0.014, 0.26, 24, 16), placement({0, 0, 0.13}));
    mesh.append(placed(makeBox({0.12, 0.03, 0.035}, 2), placement({0.0, 0, 0.26})));
    return mesh;
  }
  throw InvalidArgument("unknown shape '" + name + "'");
}

}  // namespace skelgrasp::geometry::shapes
