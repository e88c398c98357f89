// The words of SceneParams on the command line: plane requirement, segmentation method and the
// object choice, parsed and printed. No PCL here (scene.cpp is the PCL translation unit).
#include <algorithm>
#include <sstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/perception/scene.h"

namespace skelgrasp::perception {

PlaneRequirement parsePlaneRequirement(const std::string& text) {
  if (text == "required") return PlaneRequirement::kRequired;
  if (text == "optional") return PlaneRequirement::kOptional;
  if (text == "none") return PlaneRequirement::kNone;
  throw InvalidArgument("unknown plane requirement '" + text +
                        "' (use required, optional or none)");
}

const char* toString(PlaneRequirement requirement) {
  switch (requirement) {
    case PlaneRequirement::kRequired:
      return "required";
    case PlaneRequirement::kOptional:
      return "optional";
    case PlaneRequirement::kNone:
      return "none";
  }
  return "?";
}

SegmentationMethod parseSegmentationMethod(const std::string& text) {
  if (text == "lccp") return SegmentationMethod::kLccp;
  if (text == "euclidean") return SegmentationMethod::kEuclidean;
  throw InvalidArgument("unknown segmentation method '" + text + "' (use lccp or euclidean)");
}

const char* toString(SegmentationMethod method) {
  switch (method) {
    case SegmentationMethod::kLccp:
      return "lccp";
    case SegmentationMethod::kEuclidean:
      return "euclidean";
  }
  return "?";
}

TargetSpec TargetSpec::parse(const std::string& text) {
  TargetSpec spec;
  if (text == "largest") return spec;
  if (text == "all") {
    spec.mode = TargetMode::kAll;
    return spec;
  }
  const std::string prefix = "nearest:";
  if (text.rfind(prefix, 0) == 0) {
    std::string rest = text.substr(prefix.size());
    std::replace(rest.begin(), rest.end(), ',', ' ');
    std::istringstream in(rest);
    double x, y, z;
    std::string extra;
    if ((in >> x >> y >> z) && !(in >> extra)) {
      spec.mode = TargetMode::kNearest;
      spec.point = {x, y, z};
      return spec;
    }
  }
  const std::string index_prefix = "index:";
  if (text.rfind(index_prefix, 0) == 0) {
    const std::string digits = text.substr(index_prefix.size());
    // Digits only (no sign, no spaces) and few enough of them that the value fits: an object
    // index is a small count.
    constexpr std::size_t kMaxIndexDigits = 9;
    if (!digits.empty() && digits.size() <= kMaxIndexDigits &&
        std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      spec.mode = TargetMode::kIndex;
      spec.index = std::stoul(digits);
      return spec;
    }
  }
  throw InvalidArgument("bad object selection '" + text +
                        "' (use largest, all, nearest:x,y,z or index:k)");
}

std::string TargetSpec::toString() const {
  switch (mode) {
    case TargetMode::kLargest:
      return "largest";
    case TargetMode::kAll:
      return "all";
    case TargetMode::kNearest: {
      std::ostringstream out;
      out << "nearest:" << point.x() << "," << point.y() << "," << point.z();
      return out.str();
    }
    case TargetMode::kIndex:
      return "index:" + std::to_string(index);
  }
  return "?";
}

}  // namespace skelgrasp::perception
