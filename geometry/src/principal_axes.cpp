#include "skelgrasp/geometry/principal_axes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace skelgrasp::geometry {

PrincipalAxes surfacePrincipalAxes(const TriangleMesh& mesh) {
  // Exact moments of uniformly dense triangles: E[x] = (a+b+c)/3 and
  // E[x x^T] = (a a^T + b b^T + c c^T + s s^T) / 12 with s = a+b+c. Area weights make the axes
  // independent of how finely each part is meshed (vertex moments are not).
  double area = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (std::size_t f = 0; f < mesh.numFaces(); ++f) {
    const double w = mesh.faceArea(f);
    const auto& t = mesh.faces[f];
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]],
                          &c = mesh.vertices[t[2]];
    const Eigen::Vector3d s = a + b + c;
    area += w;
    first += w * s / 3.0;
    second +=
        w / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  PrincipalAxes out;
  if (!(area > 0)) return out;
  const Eigen::Vector3d mean = first / area;
  const Eigen::Matrix3d covariance = second / area - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  // Eigen sorts eigenvalues increasingly: reverse so column 0 is the longest axis.
  for (int i = 0; i < 3; ++i) {
    out.axes.col(i) = solver.eigenvectors().col(2 - i);
    out.sd(i) = std::sqrt(std::max(0.0, solver.eigenvalues()(2 - i)));
  }
  if (out.axes.determinant() < 0) out.axes.col(2) = -out.axes.col(2);
  return out;
}

double principalLengthM(const TriangleMesh& mesh, const PrincipalAxes& axes) {
  // No area, no axes: the identity's x would make a sliver along y look as small as a point.
  if (!(axes.sd(0) > 0)) return mesh.bounds().diagonal();
  const Eigen::Vector3d longest = axes.axes.col(0);
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const auto& v : mesh.vertices) {
    low = std::min(low, longest.dot(v));
    high = std::max(high, longest.dot(v));
  }
  return high - low;
}

FootprintExtents footprintExtents(const std::vector<Eigen::Vector3d>& points,
                                  const Eigen::Vector3d& up) {
  FootprintExtents out;
  if (points.empty()) return out;
  const Eigen::Vector3d across = up.unitOrthogonal();
  const Eigen::Vector3d along = up.cross(across);
  std::vector<Eigen::Vector2d> flat;
  flat.reserve(points.size());
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) {
    flat.emplace_back(across.dot(p), along.dot(p));
    mean += flat.back();
  }
  mean /= static_cast<double>(flat.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& q : flat) scatter += (q - mean) * (q - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(scatter);
  // Eigenvalues ascend: column 1 is the major axis, column 0 the minor.
  const auto extentAlong = [&](const Eigen::Vector2d& axis) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const auto& q : flat) {
      low = std::min(low, axis.dot(q));
      high = std::max(high, axis.dot(q));
    }
    return high - low;
  };
  out.widest_m = extentAlong(axes.eigenvectors().col(1));
  out.narrowest_m = extentAlong(axes.eigenvectors().col(0));
  return out;
}

}  // namespace skelgrasp::geometry
