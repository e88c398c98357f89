#include "skelgrasp/presentation/scene_view.h"

#include <boost/archive/iterators/base64_from_binary.hpp>
#include <boost/archive/iterators/transform_width.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>

#include "skelgrasp/common/error.h"
#include "skelgrasp/presentation/html_report.h"

namespace skelgrasp::presentation {
namespace {

// 16-bit positions within an item's bounding box: 1/65535 of its extent (15 µm over a 1 m scan),
// far below what a person sees when turning the view.
constexpr double kQuantisationSteps = std::numeric_limits<std::uint16_t>::max();
// Extents below this are treated as this (a flat or single-point item still decodes).
constexpr double kMinExtentM = 1e-9;

std::string base64(const std::uint8_t* data, std::size_t size) {
  using namespace boost::archive::iterators;
  using Encoder = base64_from_binary<transform_width<const std::uint8_t*, 6, 8>>;
  std::string out(Encoder(data), Encoder(data + size));
  out.append((3 - size % 3) % 3, '=');
  return out;
}

template <typename T>
std::string base64Of(const std::vector<T>& values) {
  return base64(reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(T));
}

// Little-endian typed arrays are what JavaScript's typed arrays read on every browser platform.
static_assert(sizeof(std::uint16_t) == 2 && sizeof(std::uint32_t) == 4);

nlohmann::json quantisedPositions(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (points.empty()) lo = hi = Eigen::Vector3d::Zero();
  const Eigen::Vector3d scale =
      ((hi - lo).cwiseMax(Eigen::Vector3d::Constant(kMinExtentM))) / kQuantisationSteps;
  std::vector<std::uint16_t> q;
  q.reserve(points.size() * 3);
  for (const auto& p : points) {
    for (int k = 0; k < 3; ++k) {
      q.push_back(static_cast<std::uint16_t>(std::lround((p[k] - lo[k]) / scale[k])));
    }
  }
  return {{"min", {lo.x(), lo.y(), lo.z()}},
          {"scale", {scale.x(), scale.y(), scale.z()}},
          {"q", base64Of(q)}};
}

nlohmann::json colourBytes(const std::vector<Rgb>& colours) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(colours.size() * 3);
  for (const auto& c : colours) bytes.insert(bytes.end(), {c[0], c[1], c[2]});
  return base64Of(bytes);
}

nlohmann::json meshJson(const TriangleMesh& mesh, Rgb colour) {
  std::vector<std::uint32_t> index;
  index.reserve(mesh.numFaces() * 3);
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) index.push_back(static_cast<std::uint32_t>(f[k]));
  }
  nlohmann::json j = {{"pos", quantisedPositions(mesh.vertices)},
                      {"index", base64Of(index)},
                      {"colour", {colour[0], colour[1], colour[2]}}};
  if (mesh.vertex_colors.size() == mesh.numVertices() && !mesh.vertex_colors.empty()) {
    j["colors"] = colourBytes(mesh.vertex_colors);
  }
  return j;
}

std::size_t base64Bytes(const nlohmann::json& j) {
  if (j.is_string()) return j.get_ref<const std::string&>().size();
  std::size_t n = 0;
  if (j.is_structured()) {
    for (const auto& v : j) n += base64Bytes(v);
  }
  return n;
}

// Column-major 4x4, what THREE.Matrix4.fromArray reads.
std::vector<double> matrixArray(const Pose& pose) {
  const Eigen::Matrix4d m = pose.matrix();
  return std::vector<double>(m.data(), m.data() + 16);
}

// The embedded JSON must not end its <script> element early.
std::string scriptSafe(std::string text) {
  for (std::size_t at = 0; (at = text.find("</", at)) != std::string::npos; at += 3) {
    text.replace(at, 2, "<\\/");
  }
  return text;
}

}  // namespace

void SceneView3d::addMesh(const std::string& layer, const TriangleMesh& mesh, Rgb colour,
                          double opacity) {
  if (!(opacity > 0 && opacity <= 1))
    throw InvalidArgument("scene view: opacity must be in (0, 1]");
  if (mesh.empty()) return;
  nlohmann::json item = meshJson(mesh, colour);
  item["kind"] = "mesh";
  item["layer"] = layer;
  item["opacity"] = opacity;
  data_bytes_ += base64Bytes(item);
  items_.push_back(std::move(item));
}

void SceneView3d::addPoints(const std::string& layer, const std::vector<Eigen::Vector3d>& points,
                            const std::vector<Rgb>& colours, double size_m,
                            std::size_t max_points) {
  if (!colours.empty() && colours.size() != points.size())
    throw InvalidArgument("scene view: one colour per point, or none");
  if (!(size_m > 0) || max_points == 0)
    throw InvalidArgument("scene view: bad point size or count");
  if (points.empty()) return;
  const std::size_t stride = (points.size() + max_points - 1) / max_points;
  std::vector<Eigen::Vector3d> kept;
  std::vector<Rgb> kept_colours;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    kept.push_back(points[i]);
    if (!colours.empty()) kept_colours.push_back(colours[i]);
  }
  nlohmann::json item = {{"kind", "points"},
                         {"layer", layer},
                         {"pos", quantisedPositions(kept)},
                         {"size", size_m},
                         {"colour", {128, 128, 128}}};
  if (!kept_colours.empty()) item["colors"] = colourBytes(kept_colours);
  data_bytes_ += base64Bytes(item);
  items_.push_back(std::move(item));
}

void SceneView3d::addLines(const std::string& layer,
                           const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments,
                           Rgb colour) {
  if (segments.empty()) return;
  std::vector<Eigen::Vector3d> ends;
  for (const auto& [a, b] : segments) ends.insert(ends.end(), {a, b});
  nlohmann::json item = {{"kind", "lines"},
                         {"layer", layer},
                         {"pos", quantisedPositions(ends)},
                         {"colour", {colour[0], colour[1], colour[2]}}};
  data_bytes_ += base64Bytes(item);
  items_.push_back(std::move(item));
}

int SceneView3d::addPart(const TriangleMesh& mesh_in_part_frame, Rgb colour) {
  nlohmann::json part = meshJson(mesh_in_part_frame, colour);
  data_bytes_ += base64Bytes(part);
  parts_.push_back(std::move(part));
  return static_cast<int>(parts_.size()) - 1;
}

void SceneView3d::addGrasp(const std::string& label,
                           const std::vector<std::pair<int, Pose>>& part_poses,
                           const std::vector<SceneViewContact>& contacts) {
  nlohmann::json placed = nlohmann::json::array();
  for (const auto& [part, pose] : part_poses) {
    if (part < 0 || part >= static_cast<int>(parts_.size()))
      throw InvalidArgument("scene view: grasp uses an unknown part");
    placed.push_back({{"part", part}, {"matrix", matrixArray(pose)}});
  }
  nlohmann::json points = nlohmann::json::array();
  for (const auto& c : contacts) {
    points.push_back(
        {c.point.x(), c.point.y(), c.point.z(), c.normal.x(), c.normal.y(), c.normal.z()});
  }
  grasps_.push_back({{"label", label}, {"parts", placed}, {"contacts", points}});
}

std::size_t SceneView3d::dataBytes() const {
  return data_bytes_;
}

std::string SceneView3d::html(int height_px) const {
  const nlohmann::json data = {{"items", items_}, {"parts", parts_}, {"grasps", grasps_}};
  std::string rows;
  for (std::size_t g = 0; g < grasps_.size(); ++g) {
    rows += "<tr data-grasp=\"" + std::to_string(g) + "\"><td>" +
            escapeHtml(grasps_[g]["label"].get<std::string>()) + "</td></tr>\n";
  }
  return "<div id=\"sv3d\" class=\"sv3d\" data-status=\"loading\">\n"
         "<canvas id=\"sv3d-canvas\" style=\"width:100%;height:" +
         std::to_string(height_px) +
         "px;display:block;background:#f4f4f6;border:1px solid #ccc\"></canvas>\n"
         "<p id=\"sv3d-message\" style=\"color:#a00\"></p>\n"
         "<div id=\"sv3d-layers\"></div>\n"
         "<p>Drag to turn, scroll to zoom, right-drag to move. Click a grasp to show it.</p>\n"
         "<table id=\"sv3d-grasps\" style=\"cursor:pointer\">\n" +
         rows + "</table>\n</div>\n<script>\n" + threeJsSource() +
         "\n</script>\n<script type=\"application/json\" id=\"sv3d-data\">" +
         scriptSafe(data.dump()) + "</script>\n<script>\n" + detail::kSceneViewScript +
         "\n</script>\n";
}

}  // namespace skelgrasp::presentation
