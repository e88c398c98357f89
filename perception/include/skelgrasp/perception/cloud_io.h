#pragma once
// Point cloud files through PCL I/O: PCD (ascii, binary, binary_compressed; organised or not;
// fields x y z with optional rgb/rgba, label and normal_x/y/z) and PLY vertices. The PCD
// VIEWPOINT (sensor origin and orientation) is kept in PointCloud::sensor_origin/orientation.
#include <string>

#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/common/point_cloud.h"

namespace skelgrasp::perception {

struct CloudLoadOptions {
  // kAuto: a cloud whose finite points span a bounding-box diagonal above
  // `auto_millimetre_diagonal` (file units) is taken to be in millimetres and scaled, with a
  // warning. Household scenes in metres span at most a few metres.
  LengthUnit units = LengthUnit::kAuto;
  double auto_millimetre_diagonal = 20.0;
  // A cloud with more points than this is voxel-downsampled on load, with a warning naming the
  // point count and the voxel size: a 5-million-point scan is a normal scan, but every later
  // stage (normals, clustering, meshing) is sized for Primesense-like clouds of a few hundred
  // thousand points. The leaf is the smallest tried (growing by 1.5x) that brings the cloud
  // under this count. 0 = never downsample.
  std::size_t voxel_above_points = 2'000'000;
  // Files declaring more points than this are refused before reading. PCL reads a file whole,
  // and loading plus downsampling peaks at about 200 bytes per point (measured: 580 MB for 3
  // million xyz points), so the default bounds a load at about 4 GB. 0 = no limit.
  std::size_t max_points = 20'000'000;
};

struct CloudLoadInfo {
  std::string path;
  std::string format;      // "pcd" or "ply"
  std::size_t points = 0;  // after voxel downsampling on load, if any
  std::size_t points_in_file = 0;
  double voxel_leaf_m = 0;  // leaf of the downsampling on load; 0 when none
  std::size_t finite_points = 0;
  bool organized = false;
  double scale_to_meters = 1.0;
  bool units_guessed = false;
};

// Throws IoError("<path>: <problem>") for a missing or unreadable file, an unknown extension, a
// parse failure, a cloud without x/y/z or without points, a header declaring more points than
// the file holds (checked before anything is allocated) or more than `max_points`.
PointCloud loadPointCloud(const std::string& path, const CloudLoadOptions& options = {},
                          CloudLoadInfo* info = nullptr);

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

// Writes x y z (+ rgb, label, normals when present) and the sensor pose as VIEWPOINT; organised
// clouds keep their width and height. Throws IoError.
void savePointCloud(const std::string& path, const PointCloud& cloud,
                    PcdEncoding encoding = PcdEncoding::kBinaryCompressed);

// Unit sanity for clouds from any source: applies the rule of CloudLoadOptions to `cloud` in
// place and returns the scale applied (1 when unchanged). `source` names the data in the warning.
double normaliseUnits(PointCloud& cloud, const CloudLoadOptions& options, const std::string& source,
                      bool* guessed = nullptr);

}  // namespace skelgrasp::perception
