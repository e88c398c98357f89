#include "skelgrasp/datasets/input.h"

#include <filesystem>

#include "skelgrasp/common/error.h"

namespace skelgrasp::datasets {

const char* toString(InputKind kind) {
  switch (kind) {
    case InputKind::kCloud:
      return "cloud";
    case InputKind::kCapture:
      return "capture";
    case InputKind::kYcbRaw:
      return "ycb_raw";
  }
  return "?";
}

perception::Scan loadInput(const std::string& path, const InputOptions& options, InputKind* kind) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "no such file or directory");
  if (fs::is_directory(path, ec)) {
    if (kind) *kind = InputKind::kYcbRaw;
    return loadYcbRaw(path, options.ycb).scan;
  }
  const std::string ext = fileExtension(path);
  if (ext == "json") {
    if (kind) *kind = InputKind::kCapture;
    return perception::loadCapture(path, options.units);
  }
  if (ext == "pcd" || ext == "ply") {
    if (kind) *kind = InputKind::kCloud;
    perception::Scan scan;
    scan.cloud = perception::loadPointCloud(path, options.units);
    scan.source = path;
    // Normals stored with a cloud were oriented by whoever fused it (several views): keep them
    // rather than turning them all towards the one viewpoint the file names.
    scan.per_view_normals = scan.cloud.hasNormals();
    return scan;
  }
  throw IoError(path, "unknown input '." + ext +
                          "' (expected a .pcd/.ply cloud, a .json capture description or a YCB raw "
                          "capture folder)");
}

}  // namespace skelgrasp::datasets
