#include "skelgrasp/geometry/surface_distance.h"

#include <algorithm>
#include <random>

#include "skelgrasp/common/error.h"
#include "skelgrasp/geometry/mesh_query.h"

namespace skelgrasp::geometry {
namespace {

struct OneWay {
  double mean = 0, p95 = 0, max = 0;
};

OneWay distances(const std::vector<Eigen::Vector3d>& samples, const TriangleMesh& target) {
  const MeshQuery query(target);
  std::vector<double> d;
  d.reserve(samples.size());
  for (const auto& p : samples) d.push_back(query.distance(p));
  OneWay out;
  if (d.empty()) return out;
  for (double x : d) out.mean += x;
  out.mean /= static_cast<double>(d.size());
  std::sort(d.begin(), d.end());
  out.p95 = d[static_cast<std::size_t>(0.95 * static_cast<double>(d.size() - 1))];
  out.max = d.back();
  return out;
}

}  // namespace

std::vector<Eigen::Vector3d> sampleSurface(const TriangleMesh& mesh, std::size_t count,
                                           std::uint64_t seed) {
  if (mesh.empty()) throw InvalidArgument("sampleSurface: empty mesh");
  std::vector<double> cumulative(mesh.faces.size());
  double total = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    total += mesh.faceArea(f);
    cumulative[f] = total;
  }
  if (!(total > 0)) throw InvalidArgument("sampleSurface: mesh has zero area");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double pick = uniform(rng) * total;
    const std::size_t f = static_cast<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const auto& t = mesh.faces[std::min(f, mesh.faces.size() - 1)];
    double r1 = uniform(rng), r2 = uniform(rng);
    if (r1 + r2 > 1.0) {  // fold the unit square onto the triangle
      r1 = 1.0 - r1;
      r2 = 1.0 - r2;
    }
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    samples.push_back(a + r1 * (mesh.vertices[t[1]] - a) + r2 * (mesh.vertices[t[2]] - a));
  }
  return samples;
}

ChamferDistance chamferDistance(const TriangleMesh& a, const TriangleMesh& b, std::size_t samples,
                                std::uint64_t seed) {
  const OneWay ab = distances(sampleSurface(a, samples, seed), b);
  const OneWay ba = distances(sampleSurface(b, samples, seed + 1), a);
  ChamferDistance c;
  c.a_to_b_mean_m = ab.mean;
  c.b_to_a_mean_m = ba.mean;
  c.symmetric_m = 0.5 * (ab.mean + ba.mean);
  c.a_to_b_p95_m = ab.p95;
  c.b_to_a_p95_m = ba.p95;
  c.max_m = std::max(ab.max, ba.max);
  return c;
}

}  // namespace skelgrasp::geometry
