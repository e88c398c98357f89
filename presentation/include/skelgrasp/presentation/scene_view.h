#pragma once
// An interactive 3D view for HTML reports (docs/report.md): meshes, point clouds, line sets and
// "grasps" (posed copies of shared part meshes plus contact points), drawn by three.js, which is
// inlined with the data so the page works offline and from a copied folder. Geometry is embedded
// compactly: positions quantised to 16 bits within each item's bounding box, colours as bytes,
// indices as 32-bit integers, all base64.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/common/pose.h"

namespace skelgrasp::presentation {

struct SceneViewContact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

class SceneView3d {
 public:
  // A mesh in the scene frame, drawn with its vertex colours (else `colour`). Layers can be
  // switched on and off in the page.
  void addMesh(const std::string& layer, const TriangleMesh& mesh, Rgb colour,
               double opacity = 1.0);
  // Points (at most `max_points`, an evenly strided subset otherwise), `size_m` wide.
  void addPoints(const std::string& layer, const std::vector<Eigen::Vector3d>& points,
                 const std::vector<Rgb>& colours, double size_m, std::size_t max_points);
  void addLines(const std::string& layer,
                const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& segments,
                Rgb colour);
  // A part shared by all grasps (e.g. one hand link's geometry in the link frame); its id.
  int addPart(const TriangleMesh& mesh_in_part_frame, Rgb colour);
  // One grasp: parts at poses in the scene frame, contacts, and a label for its table row.
  void addGrasp(const std::string& label, const std::vector<std::pair<int, Pose>>& part_poses,
                const std::vector<SceneViewContact>& contacts);

  std::size_t numGrasps() const { return grasps_.size(); }
  // The view as an HTML fragment: a canvas, a layer switch, a grasp table, three.js and the data.
  // `height_px` is the canvas height (its width follows the page).
  std::string html(int height_px = 480) const;
  // Bytes of embedded geometry (base64), without three.js.
  std::size_t dataBytes() const;

 private:
  std::vector<nlohmann::json> items_;
  std::vector<nlohmann::json> parts_;
  std::vector<nlohmann::json> grasps_;
  std::size_t data_bytes_ = 0;
};

// three.js (Debian libjs-three, embedded at build time) and its OrbitControls.
const std::string& threeJsSource();

namespace detail {
// The viewer's own JavaScript (common/src/scene_view_script.cpp).
extern const char* const kSceneViewScript;
}  // namespace detail

}  // namespace skelgrasp::presentation
