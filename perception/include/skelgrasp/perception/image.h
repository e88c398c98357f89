#pragma once
// Minimal row-major image containers for depth images, masks and per-pixel labels. Pixel (u, v)
// is column u, row v; the pinhole model maps pixel centres to integer (u, v).
#include <cstdint>
#include <vector>

namespace skelgrasp::perception {

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> data;  // row-major, width * height

  Image() = default;
  Image(int w, int h, T fill = T{})
      : width(w),
        height(h),
        data(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

  bool empty() const { return data.empty(); }
  bool contains(int u, int v) const { return u >= 0 && v >= 0 && u < width && v < height; }
  T& at(int u, int v) { return data[static_cast<std::size_t>(v) * width + u]; }
  const T& at(int u, int v) const { return data[static_cast<std::size_t>(v) * width + u]; }
};

using DepthImage = Image<float>;         // metres; NaN or 0 = no depth
using MaskImage = Image<std::uint8_t>;   // 0 = background, nonzero = selected
using LabelImage = Image<std::int32_t>;  // e.g. index of the mesh seen at a pixel, -1 = none

}  // namespace skelgrasp::perception
