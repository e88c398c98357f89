// Capture descriptions: one RGB-D view described by a small JSON file.
#include <filesystem>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/scan.h"

namespace skelgrasp::perception {
namespace {

namespace fs = std::filesystem;

std::string resolve(const std::string& description, const std::string& relative) {
  const fs::path p(relative);
  if (p.is_absolute()) return p.string();
  return (fs::path(description).parent_path() / p).lexically_normal().string();
}

std::string requireFile(const std::string& description, const nlohmann::json& j,
                        const std::string& key, bool required) {
  if (!j.contains(key)) {
    if (required) throw IoError(description, "capture description lacks \"" + key + "\"");
    return {};
  }
  if (!j[key].is_string()) throw IoError(description, "\"" + key + "\" must be a file path");
  const std::string path = resolve(description, j[key].get<std::string>());
  if (!fs::exists(path))
    throw IoError(path, "no such file (\"" + key + "\" of " + description + ")");
  return path;
}

double number(const std::string& description, const nlohmann::json& j, const std::string& key,
              double fallback) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) throw IoError(description, "\"" + key + "\" must be a number");
  return j[key].get<double>();
}

}  // namespace

CaptureDescription readCaptureDescription(const std::string& path) {
  const nlohmann::json j = readJsonFile(path);
  if (!j.is_object()) throw IoError(path, "capture description must be a JSON object");
  CaptureDescription d;
  d.path = path;
  d.depth = requireFile(path, j, "depth", true);
  d.mask = requireFile(path, j, "mask", false);
  d.color = requireFile(path, j, "color", false);
  const std::string ext = fileExtension(d.depth);
  if (ext != "npy" && ext != "png") {
    throw IoError(path, "\"depth\" must be a .npy or 16-bit .png file, got '." + ext + "'");
  }
  d.depth_scale = number(path, j, "depth_scale", ext == "png" ? 0.001 : 1.0);
  if (!(d.depth_scale > 0)) throw IoError(path, "\"depth_scale\" must be positive");

  if (!j.contains("intrinsics")) throw IoError(path, "capture description lacks \"intrinsics\"");
  if (j["intrinsics"].is_string()) {
    d.intrinsics = readIntrinsicsJson(requireFile(path, j, "intrinsics", true));
  } else if (j["intrinsics"].is_object()) {
    d.intrinsics = intrinsicsFromJson(j["intrinsics"], path);
  } else {
    throw IoError(path, "\"intrinsics\" must be a file path or an object");
  }

  if (j.contains("camera_to_world")) {
    const auto& t = j["camera_to_world"];
    if (!t.is_string()) throw IoError(path, "\"camera_to_world\" must be a string");
    const std::string text = t.get<std::string>();
    const std::string candidate = resolve(path, text);
    if (fs::exists(candidate) && !fs::is_directory(candidate)) {
      d.camera_to_world = readTransformText(candidate);
    } else {
      try {
        d.camera_to_world = parsePose(text);
      } catch (const InvalidArgument& e) {
        throw IoError(path, "\"camera_to_world\" is neither an existing file nor a pose: " +
                                std::string(e.what()));
      }
    }
  }
  d.conversion.min_depth_m = number(path, j, "min_depth_m", 0.0);
  d.conversion.max_depth_m = number(path, j, "max_depth_m", 10.0);
  if (!(d.conversion.max_depth_m > d.conversion.min_depth_m)) {
    throw IoError(path, "\"max_depth_m\" must exceed \"min_depth_m\"");
  }
  return d;
}

Scan loadCapture(const std::string& path, const CloudLoadOptions& options) {
  const CaptureDescription d = readCaptureDescription(path);
  // The declared size is checked against the intrinsics before the image is decoded.
  const ImageSize declared = readDepthImageSize(d.depth);
  if (declared.width != d.intrinsics.width || declared.height != d.intrinsics.height) {
    throw IoError(d.depth, "depth image is " + std::to_string(declared.width) + "x" +
                               std::to_string(declared.height) + " but the intrinsics say " +
                               std::to_string(d.intrinsics.width) + "x" +
                               std::to_string(d.intrinsics.height));
  }
  const DepthImage depth = fileExtension(d.depth) == "npy" ? readDepthNpy(d.depth, d.depth_scale)
                                                           : readDepthPng(d.depth, d.depth_scale);
  if (depth.width != d.intrinsics.width || depth.height != d.intrinsics.height) {
    throw IoError(d.depth, "depth image is " + std::to_string(depth.width) + "x" +
                               std::to_string(depth.height) + " but the intrinsics say " +
                               std::to_string(d.intrinsics.width) + "x" +
                               std::to_string(d.intrinsics.height));
  }
  MaskImage mask;
  if (!d.mask.empty()) {
    mask = readMaskImage(d.mask);
    if (mask.width != depth.width || mask.height != depth.height) {
      throw IoError(d.mask, "mask size differs from the depth image");
    }
  }
  Image<Rgb> color;
  if (!d.color.empty()) {
    color = readColorImage(d.color);
    if (color.width != depth.width || color.height != depth.height) {
      log().warn("{}: colour image size differs from the depth image; colours ignored", d.color);
      color = {};
    }
  }
  Scan scan;
  scan.source = path;
  scan.cloud = depthToPointCloud(depth, d.intrinsics, d.camera_to_world, nullptr,
                                 color.empty() ? nullptr : &color, d.conversion);
  if (!mask.empty()) {
    scan.object_mask.resize(mask.data.size());
    for (std::size_t i = 0; i < mask.data.size(); ++i) scan.object_mask[i] = mask.data[i] ? 1 : 0;
  }
  normaliseUnits(scan.cloud, options, path);
  std::size_t valid = 0, masked = 0;
  for (std::size_t i = 0; i < scan.cloud.size(); ++i) {
    if (!scan.cloud.points[i].allFinite()) continue;
    ++valid;
    if (!scan.object_mask.empty() && scan.object_mask[i]) ++masked;
  }
  if (valid == 0) throw IoError(d.depth, "no pixel has a valid depth");
  log().info("{}: {}x{} depth, {} valid pixels{}", path, depth.width, depth.height, valid,
             mask.empty() ? "" : fmt::format(", {} in the object mask", masked));
  return scan;
}

}  // namespace skelgrasp::perception
