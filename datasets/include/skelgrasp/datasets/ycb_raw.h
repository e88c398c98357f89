#pragma once
// YCB raw RGB-D captures ("<id>_berkeley_rgbd" archives): five Carmine RGB-D units NP1..NP5 on an
// arc around a turntable, 120 turntable angles (0..357, step 3). Per unit and angle:
//   NP{k}_{angle}.h5              dataset "depth": uint16 480x640 IR-camera depth, 0 = missing;
//                                 metres = value * NP{k}_ir_depth_scale * 1e-4
//   masks/NP{k}_{angle}_mask.pbm  object mask in the RGB camera's image (object pixels black)
//   poses/NP5_{angle}_pose.h5     "H_table_from_reference_camera" (4x4): NP5 (RGB) -> turntable
//   calibration.h5                NP{k}_ir_K, NP{k}_rgb_K (3x3), NP{k}_ir_depth_scale,
//                                 H_NP{k}_from_NP5 (NP5 -> RGB k), H_NP{k}_ir_from_NP5 (NP5 -> IR
//                                 k)
// The loader back-projects each depth image with the IR intrinsics, keeps the pixels whose
// projection into the RGB mask is object, maps them into the turntable frame
// (H_table_from_reference_camera * inv(H_NP{k}_ir_from_NP5)) and fuses the views.
#include <string>
#include <vector>

#include "skelgrasp/perception/filters.h"
#include "skelgrasp/perception/scan.h"

namespace skelgrasp::datasets {

struct YcbRawParams {
  // NP units to fuse; empty = every unit with a depth image at the first chosen angle.
  std::vector<int> cameras;
  // Angles in degrees; empty = every angle on disk that is a multiple of angle_step_deg.
  std::vector<int> angles;
  int angle_step_deg = 15;  // 24 turntable positions x 5 cameras by default
  int reference_camera = 5;
  // YCB and BigBIRD masks mark the object black (PBM bit 1).
  bool mask_object_is_black = true;
  // The reference scripts drop depth pixels whose 7x7 neighbourhood jumps by more than 0.1 m.
  int discontinuity_window = 7;
  double discontinuity_jump_m = 0.1;
  double min_depth_m = 0.2;
  double max_depth_m = 2.0;
  perception::NormalParams normals;  // estimated per view, oriented to that view's IR camera
};

struct YcbRawView {
  int camera = 0;
  int angle = 0;
  std::size_t valid_pixels = 0;
  std::size_t object_points = 0;
  Eigen::Vector3d camera_position = Eigen::Vector3d::Zero();  // IR camera, turntable frame
};

struct YcbRawCapture {
  perception::Scan scan;  // fused object points with per-view normals, turntable frame, metres
  std::vector<YcbRawView> views;
  std::string folder;
};

// The folder holding calibration.h5: `path` itself or its single sub-folder (the archives unpack
// to "<id>/"). Empty when neither is a YCB raw capture.
std::string findYcbRawFolder(const std::string& path);

// Throws IoError naming the file for a missing or malformed piece, InvalidArgument for bad
// parameters.
YcbRawCapture loadYcbRaw(const std::string& path, const YcbRawParams& params = {});

}  // namespace skelgrasp::datasets
