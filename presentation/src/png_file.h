#pragma once
// PNG encoding with libpng. The drawing code keeps OpenCV's image buffer and 2D primitives, but
// encoding through libpng instead of cv::imwrite spares every program that writes a picture
// OpenCV's imgcodecs, whose GDAL and codec libraries are ~120 shared libraries loaded at start.
#include <cstddef>
#include <cstdint>
#include <string>

namespace skelgrasp::presentation::internal {

// Writes an 8-bit 3-channel image stored as BGR rows (OpenCV's order) to `path`, atomically
// (temporary sibling + rename). Throws InvalidArgument for bad sizes, IoError when writing fails.
void writeBgrPng(const std::string& path, int width, int height, const std::uint8_t* pixels,
                 std::size_t row_stride_bytes);

}  // namespace skelgrasp::presentation::internal
