// PCL translation unit: PCD and PLY point cloud files.
#include "skelgrasp/perception/cloud_io.h"

#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/constants.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/internal/cloud_file_check.h"
#include "skelgrasp/internal/pcl_conversions.h"
#include "skelgrasp/perception/cloud_ops.h"
#include "skelgrasp/perception/filters.h"

namespace skelgrasp::perception {
namespace {

// PCL reports problems on its own console; skelgrasp reports them as one IoError line instead.
void silencePcl() {
  static const bool once = [] {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    return true;
  }();
  (void)once;
}

void checkReadable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path, "no such file");
  if (fs::is_directory(path, ec))
    throw IoError(path, "is a directory, expected a point cloud file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw IoError(path, "cannot open for reading");
  if (fs::file_size(path, ec) == 0) throw IoError(path, "file is empty");
}

// PCDReader::read trusts a header that readHeader accepted, and readHeader accepts text without
// a single PCD keyword (no fields, no points), on which read then crashes: check it first.
void checkPcdHeader(pcl::PCDReader& reader, const std::string& path) {
  pcl::PCLPointCloud2 header;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_start = 0;
  if (reader.readHeader(path, header, origin, orientation, version, data_type, data_start) < 0) {
    throw IoError(path, "cannot parse pcd header");
  }
  if (header.fields.empty()) throw IoError(path, "cannot parse pcd header: no FIELDS");
  for (const auto& f : header.fields) {
    const bool size_ok = f.datatype >= pcl::PCLPointField::INT8 &&
                         f.datatype <= pcl::PCLPointField::FLOAT64 && f.count >= 1;
    if (!size_ok) throw IoError(path, "cannot parse pcd header: bad field '" + f.name + "'");
  }
  if (std::size_t{header.width} * header.height == 0)
    throw IoError(path, "point cloud has no points");
  if (data_start == 0) throw IoError(path, "cannot parse pcd header: no DATA line");
}

// Peak memory per point of loading and voxel-downsampling a cloud (PCL's blob, skelgrasp's copy,
// the filter's copies); measured 580 MB for 3 million xyz points. Used for the refusal message.
constexpr double kPeakBytesPerPoint = 200;
// Growth of the voxel leaf between attempts to bring a large cloud under the point cap.
constexpr double kLeafGrowth = 1.5;
constexpr int kMaxLeafAttempts = 30;
// Added to each box side (metres) so a flat or single-point cloud has a nonzero volume.
constexpr double kFlatExtentPaddingM = 1e-9;

// Smallest leaf for which PCL's voxel grid (32-bit voxel indices) does not refuse the box.
double smallestIndexableLeaf(const AxisAlignedBox& box) {
  const double cells = static_cast<double>(std::numeric_limits<std::int32_t>::max()) / 2;
  return std::cbrt((box.extent().array() + kFlatExtentPaddingM).prod() / cells);
}

// Voxel-downsamples `cloud` until it has at most `cap` points. A scan is a surface, so a leaf of
// about diagonal / sqrt(cap) leaves at most ~cap occupied voxels; start below that and grow.
PointCloud downsampleToCap(const PointCloud& cloud, std::size_t cap, double* leaf_used) {
  const AxisAlignedBox box = cloud.bounds();
  double leaf = std::max(box.diagonal() / std::sqrt(static_cast<double>(cap)) / 2,
                         smallestIndexableLeaf(box));
  FilterParams params;
  params.sor_mean_k = 0;
  for (int attempt = 0; attempt < kMaxLeafAttempts; ++attempt, leaf *= kLeafGrowth) {
    params.voxel_leaf_m = leaf;
    FilterResult filtered = filterCloud(cloud, params);
    if (!filtered.status.ok()) break;
    if (filtered.cloud.size() <= cap) {
      *leaf_used = leaf;
      filtered.cloud.sensor_origin = cloud.sensor_origin;
      filtered.cloud.sensor_orientation = cloud.sensor_orientation;
      return std::move(filtered.cloud);
    }
  }
  *leaf_used = 0;
  return cloud;
}

}  // namespace

double normaliseUnits(PointCloud& cloud, const CloudLoadOptions& options, const std::string& source,
                      bool* guessed) {
  if (guessed) *guessed = false;
  double scale = 1.0;
  switch (options.units) {
    case LengthUnit::kMeters:
      return 1.0;
    case LengthUnit::kMillimeters:
      scale = kMetresPerMillimetre;
      break;
    case LengthUnit::kAuto: {
      const double diagonal = cloud.bounds().diagonal();
      if (!(diagonal > options.auto_millimetre_diagonal)) return 1.0;
      scale = kMetresPerMillimetre;
      if (guessed) *guessed = true;
      log().warn(
          "{}: bounding-box diagonal {:.4g} exceeds {:.4g}, assuming millimetres and scaling to "
          "metres (pass --units m to keep the values)",
          source, diagonal, options.auto_millimetre_diagonal);
      break;
    }
  }
  for (auto& p : cloud.points) p *= scale;
  cloud.sensor_origin *= scale;
  return scale;
}

PointCloud loadPointCloud(const std::string& path, const CloudLoadOptions& options,
                          CloudLoadInfo* info) {
  silencePcl();
  checkReadable(path);
  const std::string ext = fileExtension(path);
  if (ext != "pcd" && ext != "ply") {
    throw IoError(path, "unknown point cloud format '." + ext + "' (supported: .pcd .ply)");
  }
  // Before PCL sizes its buffers from the header.
  const internal::DeclaredCloud declared =
      ext == "pcd" ? internal::checkPcdDeclaredSize(path) : internal::checkPlyCloudHeader(path);
  if (options.max_points > 0 && declared.points > options.max_points) {
    const double gigabytes = static_cast<double>(declared.points) * kPeakBytesPerPoint / 1e9;
    throw IoError(path, fmt::format("declares {} points, more than the limit of {} (about {:.3g} "
                                    "GB to load); crop or downsample the file first",
                                    declared.points, options.max_points, gigabytes));
  }
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  int status = -1;
  try {
    if (ext == "pcd") {
      pcl::PCDReader reader;
      int version = 0;
      checkPcdHeader(reader, path);
      status = reader.read(path, blob, origin, orientation, version);
    } else {
      pcl::PLYReader reader;
      int version = 0;
      status = reader.read(path, blob, origin, orientation, version);
    }
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw IoError(path, std::string("cannot parse ") + ext + " file: " + e.what());
  }
  if (status < 0) {
    throw IoError(path, "cannot parse " + ext +
                            " file (malformed header, truncated or corrupt data, or unsupported "
                            "encoding)");
  }
  if (std::size_t{blob.width} * blob.height == 0 || blob.data.empty()) {
    throw IoError(path, "point cloud has no points");
  }
  if (blob.data.size() < std::size_t{blob.row_step} * blob.height) {
    throw IoError(path, "point data is truncated");
  }
  PointCloud cloud;
  std::string problem;
  if (!internal::fromBlob(blob, cloud, problem)) throw IoError(path, problem);
  cloud.sensor_origin = origin.head<3>().cast<double>();
  cloud.sensor_orientation = orientation.cast<double>().normalized();

  CloudLoadInfo local;
  local.path = path;
  local.format = ext;
  local.points_in_file = cloud.size();
  local.scale_to_meters = normaliseUnits(cloud, options, path, &local.units_guessed);
  if (options.voxel_above_points > 0 && cloud.size() > options.voxel_above_points) {
    Stopwatch watch;
    const std::size_t before = cloud.size();
    cloud = downsampleToCap(cloud, options.voxel_above_points, &local.voxel_leaf_m);
    if (local.voxel_leaf_m > 0) {
      log().warn(
          "{}: {} points exceed the load limit of {}; voxel-downsampled with a {:.4g} m leaf to "
          "{} points ({:.1f} s)",
          path, before, options.voxel_above_points, local.voxel_leaf_m, cloud.size(),
          watch.seconds());
    } else {
      log().warn(
          "{}: {} points exceed the load limit of {}, but no voxel size brings them under "
          "it; keeping all points",
          path, before, options.voxel_above_points);
    }
  }
  local.points = cloud.size();
  local.finite_points = countFinite(cloud);
  local.organized = cloud.isOrganized();
  log().debug("{}: {} points ({} finite){}", path, local.points, local.finite_points,
              local.organized ? fmt::format(", organised {}x{}", cloud.width, cloud.height) : "");
  if (info) *info = local;
  return cloud;
}

void savePointCloud(const std::string& path, const PointCloud& cloud, PcdEncoding encoding) {
  silencePcl();
  if (fileExtension(path) != "pcd") throw IoError(path, "point clouds are written as .pcd");
  const pcl::PCLPointCloud2 blob = internal::toBlob(cloud);
  const Eigen::Vector4f origin(static_cast<float>(cloud.sensor_origin.x()),
                               static_cast<float>(cloud.sensor_origin.y()),
                               static_cast<float>(cloud.sensor_origin.z()), 0.0f);
  const Eigen::Quaternionf orientation = cloud.sensor_orientation.cast<float>();
  writeFileViaTemporary(path, [&](const std::string& temporary) {
    pcl::PCDWriter writer;
    int status = -1;
    try {
      switch (encoding) {
        case PcdEncoding::kAscii:
          status = writer.writeASCII(temporary, blob, origin, orientation, 8);
          break;
        case PcdEncoding::kBinary:
          status = writer.writeBinary(temporary, blob, origin, orientation);
          break;
        case PcdEncoding::kBinaryCompressed:
          status = writer.writeBinaryCompressed(temporary, blob, origin, orientation);
          break;
      }
    } catch (const std::exception& e) {
      throw IoError(temporary, std::string("write failed: ") + e.what());
    }
    if (status < 0) throw IoError(temporary, "write failed");
  });
}

}  // namespace skelgrasp::perception
