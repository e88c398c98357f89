#pragma once
// Reading and writing the images of RGB-D captures: masks and colour images through OpenCV
// (PNG, PBM/PGM, JPEG, ...), depth as NumPy .npy arrays or 16-bit PNG. Every function throws
// IoError("<path>: <problem>") for a missing, unreadable or malformed file.
#include <string>

#include "skelgrasp/common/mesh.h"
#include "skelgrasp/perception/image.h"

namespace skelgrasp::perception {

// 8-bit single-channel image (colour images are converted to grey). A PBM bitmap reads as
// 0 for black (bit 1) and 255 for white (bit 0), as OpenCV decodes it.
MaskImage readMaskImage(const std::string& path);
// PNG, or binary PBM (P4) for a .pbm path: nonzero pixels become white (bit 0), zero pixels black
// (bit 1), i.e. the inverse of readMaskImage's decoding, so a round trip is exact for 0/255 masks.
void writeMaskImage(const std::string& path, const MaskImage& mask);

Image<Rgb> readColorImage(const std::string& path);
void writeColorImage(const std::string& path, const Image<Rgb>& image);

// Depth in metres from a NumPy .npy file holding a little-endian float32, float64 or uint16 array
// of shape (H, W) or (H, W, 1), C order, multiplied by `scale` (1 for metres, 0.001 for uint16
// millimetres). Non-finite values and zeros are kept (callers treat them as missing).
DepthImage readDepthNpy(const std::string& path, double scale = 1.0);
// Writes float32 (H, W, 1) like the Primesense captures the project reads.
void writeDepthNpy(const std::string& path, const DepthImage& depth);
// 16-bit single-channel PNG, values times `scale` (e.g. 0.001 for millimetres).
DepthImage readDepthPng(const std::string& path, double scale);

struct ImageSize {
  int width = 0;
  int height = 0;
};
// The size a depth image (.npy or 16-bit single-channel .png) declares, read from its header
// alone, so that a caller can compare it with the intrinsics before decoding. Both depth readers
// apply the same checks: no side above kMaxImageSidePx (rgbd.h), the right type. Throws IoError.
ImageSize readDepthImageSize(const std::string& path);

}  // namespace skelgrasp::perception
