// assimp conversion: hand link meshes (STL, DAE, OBJ, ...) -> TriangleMesh. The only file that
// sees assimp.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <filesystem>

#include "hand_loading.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::grasping::internal {
namespace {

void appendNode(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent,
                const Eigen::Vector3d& scale, TriangleMesh& out) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      out.vertices.emplace_back(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines after triangulation
      out.faces.emplace_back(base + static_cast<int>(face.mIndices[0]),
                             base + static_cast<int>(face.mIndices[1]),
                             base + static_cast<int>(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    appendNode(scene, node->mChildren[c], transform, scale, out);
}

}  // namespace

TriangleMesh loadMeshFile(const std::string& path, const Eigen::Vector3d& scale) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "mesh file not found");
  if (!fs::is_regular_file(path, ec)) throw IoError(path, "link mesh is not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size > kMaxLinkMeshBytes) {
    throw IoError(path, "link mesh of " + std::to_string(size) + " bytes exceeds the limit of " +
                            std::to_string(kMaxLinkMeshBytes) + " bytes");
  }
  Assimp::Importer importer;
  // DAE files carry their own unit and up axis; assimp applies them to the node transforms.
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    throw IoError(path, std::string("cannot read mesh: ") + importer.GetErrorString());
  }
  TriangleMesh mesh;
  appendNode(scene, scene->mRootNode, aiMatrix4x4(), scale, mesh);
  if (mesh.faces.empty()) throw IoError(path, "mesh has no triangles");
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw IoError(path, "mesh has non-finite coordinates");
  }
  return mesh;
}

}  // namespace skelgrasp::grasping::internal
