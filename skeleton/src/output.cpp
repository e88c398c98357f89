#include "skelgrasp/skeleton/output.h"

#include <fmt/format.h>

#include "skelgrasp/common/json.h"
#include "skelgrasp/geometry/regularisation.h"

namespace skelgrasp::skeleton {

nlohmann::json skeletonToJson(const SkeletonResult& result, const TriangleMesh& input,
                              const MeshLoadInfo& load_info) {
  using nlohmann::json;
  const auto& skel = result.skeleton;
  const auto& reg = result.regularisation;
  json j;
  j["schema"] = "skelgrasp.skeleton/1";
  j["input"] = {{"path", load_info.path},
                {"format", load_info.format},
                {"vertices", input.numVertices()},
                {"faces", input.numFaces()},
                {"units", "m"},
                {"scale_to_meters", load_info.scale_to_meters},
                {"units_guessed", load_info.units_guessed}};
  j["regularisation"] = geometry::toJson(reg);
  j["status"] = {{"code", toString(result.status.code)}, {"message", result.status.message}};
  j["summary"] = {{"vertices", skel.vertices.size()},
                  {"edges", skel.edges.size()},
                  {"branch", skel.countType(VertexType::kBranch)},
                  {"endpoint", skel.countType(VertexType::kEndpoint)},
                  {"connecting", skel.countType(VertexType::kConnecting)},
                  {"segments", skel.segments.size()},
                  {"loops", skel.vertices.empty() ? 0 : skel.cycleRank()},
                  {"components", skel.components()},
                  {"surface_points", skel.num_surface_points}};
  json vertices = json::array();
  for (std::size_t i = 0; i < skel.vertices.size(); ++i) {
    const auto& v = skel.vertices[i];
    vertices.push_back({{"id", i},
                        {"position", toJson(v.position)},
                        {"type", toString(v.type)},
                        {"segment", v.segment >= 0 ? json(v.segment) : json(nullptr)},
                        {"surface_points", v.surface_points},
                        {"curvature", numberOrNull(v.curvature)}});
  }
  j["vertices"] = std::move(vertices);
  json edges = json::array();
  for (const auto& e : skel.edges) edges.push_back({e[0], e[1]});
  j["edges"] = std::move(edges);
  json segments = json::array();
  for (const auto& s : skel.segments) {
    segments.push_back({{"id", s.id},
                        {"vertices", s.vertices},
                        {"length", s.length},
                        {"ends", {toString(s.ends[0]), toString(s.ends[1])}},
                        {"end_vertices",
                         {s.end_vertices[0] >= 0 ? json(s.end_vertices[0]) : json(nullptr),
                          s.end_vertices[1] >= 0 ? json(s.end_vertices[1]) : json(nullptr)}}});
  }
  j["segments"] = std::move(segments);
  j["timing"] = {{"regularise_s", result.timing.regularise_s},
                 {"skeleton_s", result.timing.skeleton_s},
                 {"mapping_s", result.timing.mapping_s},
                 {"analysis_s", result.timing.analysis_s},
                 {"total_s", result.timing.total_s}};
  j["diagnostics"] = {{"regularised_vertices", result.diagnostics.regularised_vertices},
                      {"unassigned_mesh_vertices", result.diagnostics.unassigned_mesh_vertices},
                      {"pruned_spurs", result.diagnostics.pruned_spurs},
                      {"pruned_spur_vertices", result.diagnostics.pruned_spur_vertices},
                      {"mean_mapping_distance_m", result.diagnostics.mean_mapping_distance_m},
                      {"max_mapping_distance_m", result.diagnostics.max_mapping_distance_m}};
  return j;
}

namespace {

std::vector<int> vertexOfPoint(const TriangleMesh& input, const Skeleton& skeleton) {
  std::vector<int> owner(input.numVertices(), -1);
  for (std::size_t v = 0; v < skeleton.vertices.size(); ++v) {
    for (int p : skeleton.vertices[v].surface_points) {
      if (p >= 0 && static_cast<std::size_t>(p) < owner.size()) owner[p] = static_cast<int>(v);
    }
  }
  return owner;
}

}  // namespace

TriangleMesh colourByVertexType(const TriangleMesh& input, const Skeleton& skeleton) {
  TriangleMesh out = input;
  const auto owner = vertexOfPoint(input, skeleton);
  out.vertex_colors.assign(input.numVertices(), Rgb{128, 128, 128});
  for (std::size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    switch (skeleton.vertices[owner[i]].type) {
      case VertexType::kEndpoint:
        out.vertex_colors[i] = {220, 30, 30};
        break;
      case VertexType::kConnecting:
        out.vertex_colors[i] = {240, 210, 40};
        break;
      case VertexType::kBranch:
        out.vertex_colors[i] = {40, 80, 220};
        break;
    }
  }
  return out;
}

TriangleMesh colourBySegment(const TriangleMesh& input, const Skeleton& skeleton) {
  static const Rgb palette[] = {{230, 25, 75},  {60, 180, 75},   {255, 225, 25}, {0, 130, 200},
                                {245, 130, 48}, {145, 30, 180},  {70, 240, 240}, {240, 50, 230},
                                {210, 245, 60}, {250, 190, 212}, {0, 128, 128},  {170, 110, 40}};
  TriangleMesh out = input;
  const auto owner = vertexOfPoint(input, skeleton);
  out.vertex_colors.assign(input.numVertices(), Rgb{110, 110, 110});
  for (std::size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    const int seg = skeleton.vertices[owner[i]].segment;
    if (seg >= 0) out.vertex_colors[i] = palette[seg % (sizeof(palette) / sizeof(palette[0]))];
  }
  return out;
}

std::string summaryLine(const SkeletonResult& result, const std::string& name) {
  const auto& s = result.skeleton;
  if (!result.status.ok()) {
    return fmt::format("{}: skeleton failed ({}): {}", name, toString(result.status.code),
                       result.status.message);
  }
  const auto& reg = result.regularisation;
  return fmt::format(
      "{}: {} input vertices -> {} skeleton vertices ({} branch, {} endpoint, {} connecting), "
      "{} segments, {} loop(s); genus {} -> {}; regularise {:.2f} s, skeleton {:.2f} s",
      name, s.num_surface_points, s.vertices.size(), s.countType(VertexType::kBranch),
      s.countType(VertexType::kEndpoint), s.countType(VertexType::kConnecting), s.segments.size(),
      s.cycleRank(), reg.input.genus ? std::to_string(*reg.input.genus) : "n/a",
      reg.output.genus ? std::to_string(*reg.output.genus) : "n/a", result.timing.regularise_s,
      result.timing.skeleton_s);
}

}  // namespace skelgrasp::skeleton
