// PCL translation unit: Poisson surface reconstruction.
#include <pcl/surface/poisson.h>

#include <mutex>
#include <thread>

#include "poisson.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp::reconstruction::detail {

TriangleMesh poissonSurface(const PointCloud& oriented, const PoissonParams& params) {
  auto input = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  input->points.reserve(oriented.size());
  for (std::size_t i = 0; i < oriented.size(); ++i) {
    pcl::PointNormal q;
    q.x = static_cast<float>(oriented.points[i].x());
    q.y = static_cast<float>(oriented.points[i].y());
    q.z = static_cast<float>(oriented.points[i].z());
    q.normal_x = static_cast<float>(oriented.normals[i].x());
    q.normal_y = static_cast<float>(oriented.normals[i].y());
    q.normal_z = static_cast<float>(oriented.normals[i].z());
    q.curvature = 0.0f;
    input->points.push_back(q);
  }
  input->width = static_cast<std::uint32_t>(input->size());
  input->height = 1;
  input->is_dense = true;

  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(params.depth);
  poisson.setPointWeight(static_cast<float>(params.point_weight));
  poisson.setSamplesPerNode(static_cast<float>(params.samples_per_node));
  poisson.setScale(static_cast<float>(params.scale));
  poisson.setManifold(true);
  poisson.setOutputPolygons(false);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  poisson.setThreads(params.threads > 0 ? params.threads : cores);
  poisson.setInputCloud(input);
  pcl::PointCloud<pcl::PointNormal> vertices;
  std::vector<pcl::Vertices> polygons;
  {
    // One reconstruction at a time in the process: PCL's PoissonRecon keeps its octree's
    // allocators and neighbour tables in static members (two at once crash), and the stdout
    // silenced here is the process's.
    static std::mutex one_at_a_time;
    const std::lock_guard<std::mutex> lock(one_at_a_time);
    // PCL's PoissonRecon prints marching-cubes diagnostics ("Vertex pair not in list") with printf;
    // stdout belongs to the CLI's summaries.
    const SilencedStream quiet(SilencedStream::Stream::kStdout);
    poisson.reconstruct(vertices, polygons);
  }

  TriangleMesh mesh;
  mesh.vertices.reserve(vertices.size());
  for (const auto& v : vertices.points) mesh.vertices.emplace_back(v.x, v.y, v.z);
  mesh.faces.reserve(polygons.size());
  const auto inRange = [n = mesh.vertices.size()](auto i) {
    return i >= 0 && static_cast<std::size_t>(i) < n;
  };
  for (const auto& polygon : polygons) {
    const auto& idx = polygon.vertices;
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) {
      if (!inRange(idx[0]) || !inRange(idx[k]) || !inRange(idx[k + 1])) continue;
      mesh.faces.emplace_back(static_cast<int>(idx[0]), static_cast<int>(idx[k]),
                              static_cast<int>(idx[k + 1]));
    }
  }
  return mesh;
}

}  // namespace skelgrasp::reconstruction::detail
