// OpenCV translation unit of perception: image files and image filters. The .npy reader is here
// too: NumPy's format is a short text header and raw little-endian data, documented at
// numpy.org/doc/stable/reference/generated/numpy.lib.format.html.
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/rgbd.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/file_header.h"
#include "skelgrasp/common/logging.h"
#include "skelgrasp/common/mesh_io.h"

namespace skelgrasp::perception {
namespace {

void checkReadable(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw IoError(path, "is a directory");
  if (std::filesystem::file_size(path, ec) == 0) throw IoError(path, "file is empty");
}

cv::Mat readWithOpenCv(const std::string& path, int flags) {
  checkReadable(path);
  cv::Mat image;
  try {
    // libpng prints "libpng error: Read Error" on stderr for a truncated file before OpenCV
    // returns an empty image: our one error line below says it for the file.
    const SilencedStream quiet(SilencedStream::Stream::kStderr);
    image = cv::imread(path, flags);
  } catch (const cv::Exception& e) {
    throw IoError(path, std::string("cannot decode image: ") + e.what());
  }
  if (image.empty()) throw IoError(path, "cannot decode image (unknown format or corrupt data)");
  return image;
}

void writeWithOpenCv(const std::string& path, const cv::Mat& image,
                     const std::vector<int>& flags = {}) {
  // The temporary keeps the extension: imwrite picks the encoder from the name.
  writeFileViaTemporary(path, [&](const std::string& temporary) {
    bool ok = false;
    try {
      ok = cv::imwrite(temporary, image, flags);
    } catch (const cv::Exception& e) {
      throw IoError(temporary, std::string("cannot write image: ") + e.what());
    }
    if (!ok) throw IoError(temporary, "cannot write image");
  });
}

struct NpyHeader {
  std::string descr;
  bool fortran_order = false;
  std::vector<std::uint64_t> shape;
  std::size_t data_offset = 0;
};

NpyHeader readNpyHeader(const std::string& path, std::ifstream& in) {
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "\x93NUMPY", 6) != 0) {
    throw IoError(path, "not a NumPy .npy file (bad magic)");
  }
  const int major = static_cast<unsigned char>(magic[6]);
  std::size_t header_length = 0;
  if (major == 1) {
    unsigned char b[2];
    if (!in.read(reinterpret_cast<char*>(b), 2)) throw IoError(path, "truncated .npy header");
    header_length = b[0] | (b[1] << 8);
  } else if (major == 2 || major == 3) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) throw IoError(path, "truncated .npy header");
    header_length = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::size_t>(b[3]) << 24);
  } else {
    throw IoError(path, "unsupported .npy version " + std::to_string(major));
  }
  // The length field is up to 4 GiB in version 2: check it against the file before allocating.
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  const auto length_end = in.tellg();
  if (ec || length_end < 0 || header_length > file_size - static_cast<std::uint64_t>(length_end)) {
    throw IoError(path, "truncated .npy header: declares " + std::to_string(header_length) +
                            " bytes, the file has " + std::to_string(file_size));
  }
  std::string text(header_length, '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(header_length))) {
    throw IoError(path, "truncated .npy header");
  }
  NpyHeader header;
  header.data_offset = static_cast<std::size_t>(in.tellg());
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(R"('descr'\s*:\s*'([^']*)')"))) {
    throw IoError(path, ".npy header has no 'descr'");
  }
  header.descr = m[1];
  header.fortran_order = std::regex_search(text, std::regex(R"('fortran_order'\s*:\s*True)"));
  if (!std::regex_search(text, m, std::regex(R"('shape'\s*:\s*\(([^)]*)\))"))) {
    throw IoError(path, ".npy header has no 'shape'");
  }
  const std::string dims = m[1];
  // "(480, 640)", "(480, 640, 1)", "(5,)": comma-separated counts, a trailing comma allowed.
  std::istringstream fields(dims);
  for (std::string field; std::getline(fields, field, ',');) {
    const auto first = field.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    const auto last = field.find_last_not_of(" \t");
    header.shape.push_back(
        parseHeaderCount(path, ".npy shape dimension", field.substr(first, last - first + 1)));
  }
  return header;
}

// Rows and columns of a depth array: (H, W) or (H, W, 1), each side at most kMaxImageSidePx, so
// that a small (or sparse) file declaring a huge array is refused before anything is allocated.
ImageSize npyDepthSize(const std::string& path, const NpyHeader& header) {
  if (header.fortran_order) throw IoError(path, "Fortran-ordered .npy arrays are not supported");
  const bool shape_ok =
      (header.shape.size() == 2 || (header.shape.size() == 3 && header.shape[2] == 1)) &&
      header.shape[0] > 0 && header.shape[1] > 0;
  if (!shape_ok) throw IoError(path, "expected a depth array of shape (H, W) or (H, W, 1)");
  const std::uint64_t max_side = kMaxImageSidePx;
  if (header.shape[0] > max_side || header.shape[1] > max_side) {
    throw IoError(path, "depth array shape (" + std::to_string(header.shape[0]) + ", " +
                            std::to_string(header.shape[1]) +
                            ") exceeds the largest image side of " +
                            std::to_string(kMaxImageSidePx) + " pixels");
  }
  return {static_cast<int>(header.shape[1]), static_cast<int>(header.shape[0])};
}

// PNG signature and the start of its first chunk, which must be IHDR (PNG spec, 5.2 and 11.2.2):
// length (4), "IHDR", width (4, big-endian), height (4), bit depth (1), colour type (1).
constexpr std::size_t kPngHeaderBytes = 26;
constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr int kPngGreyColourType = 0;
constexpr int kPngDepthBits = 16;
// Deepest channel of a mask PNG (1, 2, 4 and 8-bit masks are read as they are).
constexpr int kPngMaskBits = 8;

struct PngHeader {
  std::uint32_t width = 0, height = 0;
  int bits = 0, colour_type = 0;
};

// The IHDR of a PNG file, or nothing when the file does not start with the PNG signature (another
// format: OpenCV's decoder checks it).
std::optional<PngHeader> readPngHeader(const std::string& path) {
  checkReadable(path);
  std::ifstream in(path, std::ios::binary);
  unsigned char b[kPngHeaderBytes];
  if (!in.read(reinterpret_cast<char*>(b), kPngHeaderBytes) ||
      std::memcmp(b, kPngSignature, sizeof kPngSignature) != 0) {
    return std::nullopt;
  }
  if (std::memcmp(b + 12, "IHDR", 4) != 0) throw IoError(path, "PNG file without an IHDR header");
  auto big_endian = [&](int at) {
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
           (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
  };
  return PngHeader{big_endian(16), big_endian(20), b[24], b[25]};
}

// Each side of a PNG at most kMaxImageSidePx, checked before the decoder allocates (a 1.7 MB PNG
// declaring 30000x30000 decoded into gigabytes).
void checkPngSize(const std::string& path, const PngHeader& header, const char* what) {
  const std::uint32_t max_side = kMaxImageSidePx;
  if (header.width == 0 || header.height == 0 || header.width > max_side ||
      header.height > max_side) {
    throw IoError(path, std::string(what) + " PNG declares " + std::to_string(header.width) + "x" +
                            std::to_string(header.height) + " pixels; each side must be in [1, " +
                            std::to_string(kMaxImageSidePx) + "]");
  }
}

// The size a depth PNG declares, read from its IHDR without decoding: it must be 16-bit grey (an
// RGB16 PNG decoded as depth would be a grey mix of its channels) of a size within the cap.
ImageSize pngDepthSize(const std::string& path) {
  const auto header = readPngHeader(path);
  if (!header) throw IoError(path, "not a PNG file (no PNG signature)");
  if (header->bits != kPngDepthBits || header->colour_type != kPngGreyColourType) {
    throw IoError(path, "expected a 16-bit single-channel depth PNG, the header says " +
                            std::to_string(header->bits) + "-bit colour type " +
                            std::to_string(header->colour_type));
  }
  checkPngSize(path, *header, "depth");
  return {static_cast<int>(header->width), static_cast<int>(header->height)};
}

}  // namespace

ImageSize readDepthImageSize(const std::string& path) {
  const std::string ext = fileExtension(path);
  if (ext == "png") return pngDepthSize(path);
  if (ext != "npy") throw IoError(path, "a depth image must be a .npy or 16-bit .png file");
  checkReadable(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  return npyDepthSize(path, readNpyHeader(path, in));
}

MaskImage readMaskImage(const std::string& path) {
  if (const auto header = readPngHeader(path)) {
    // A 16-bit PNG reduced to 8 bits made every nonzero pixel of a depth image a mask pixel: the
    // whole scene became the object.
    if (header->bits > kPngMaskBits) {
      throw IoError(path, "expected an 8-bit mask PNG, the header says " +
                              std::to_string(header->bits) + "-bit");
    }
    checkPngSize(path, *header, "mask");
  }
  const cv::Mat image = readWithOpenCv(path, cv::IMREAD_GRAYSCALE);
  MaskImage mask(image.cols, image.rows);
  for (int v = 0; v < image.rows; ++v) {
    std::memcpy(&mask.at(0, v), image.ptr<std::uint8_t>(v), static_cast<std::size_t>(image.cols));
  }
  return mask;
}

void writeMaskImage(const std::string& path, const MaskImage& mask) {
  if (mask.empty()) throw InvalidArgument(path + ": empty mask");
  cv::Mat image(mask.height, mask.width, CV_8UC1);
  for (int v = 0; v < mask.height; ++v) {
    for (int u = 0; u < mask.width; ++u) image.at<std::uint8_t>(v, u) = mask.at(u, v) ? 255 : 0;
  }
  std::vector<int> flags;
  if (fileExtension(path) == "pbm") flags = {cv::IMWRITE_PXM_BINARY, 1};
  writeWithOpenCv(path, image, flags);
}

Image<Rgb> readColorImage(const std::string& path) {
  if (const auto header = readPngHeader(path)) checkPngSize(path, *header, "colour");
  const cv::Mat bgr = readWithOpenCv(path, cv::IMREAD_COLOR);
  Image<Rgb> image(bgr.cols, bgr.rows);
  for (int v = 0; v < bgr.rows; ++v) {
    for (int u = 0; u < bgr.cols; ++u) {
      const auto& p = bgr.at<cv::Vec3b>(v, u);
      image.at(u, v) = {p[2], p[1], p[0]};
    }
  }
  return image;
}

void writeColorImage(const std::string& path, const Image<Rgb>& image) {
  if (image.empty()) throw InvalidArgument(path + ": empty image");
  cv::Mat bgr(image.height, image.width, CV_8UC3);
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const Rgb& c = image.at(u, v);
      bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(c[2], c[1], c[0]);
    }
  }
  writeWithOpenCv(path, bgr);
}

DepthImage readDepthNpy(const std::string& path, double scale) {
  checkReadable(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open for reading");
  const NpyHeader header = readNpyHeader(path, in);
  const ImageSize size = npyDepthSize(path, header);
  std::size_t item = 0;
  if (header.descr == "<f4") {
    item = 4;
  } else if (header.descr == "<f8") {
    item = 8;
  } else if (header.descr == "<u2") {
    item = 2;
  } else {
    throw IoError(path, "unsupported .npy dtype '" + header.descr + "' (use <f4, <f8 or <u2)");
  }
  // Before allocating: the shape must fit in the bytes the file holds (rows and columns are each
  // at most kMaxImageSidePx, so the product of the two and the item size cannot overflow).
  const std::uint64_t needed = header.shape[0] * header.shape[1] * item;
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  const std::uint64_t available =
      file_size > header.data_offset ? file_size - header.data_offset : 0;
  if (ec || needed > available) {
    throw IoError(path, "truncated .npy data: shape (" + std::to_string(header.shape[0]) + ", " +
                            std::to_string(header.shape[1]) + ") of '" + header.descr + "' needs " +
                            std::to_string(needed) + " bytes, the file holds " +
                            std::to_string(available) + " after its header");
  }
  DepthImage depth(size.width, size.height);
  std::vector<char> raw(depth.data.size() * item);
  if (!in.read(raw.data(), static_cast<std::streamsize>(raw.size()))) {
    throw IoError(path, "truncated .npy data: expected " + std::to_string(raw.size()) + " bytes");
  }
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    double value = 0;
    if (item == 4) {
      float f;
      std::memcpy(&f, raw.data() + 4 * i, 4);
      value = f;
    } else if (item == 8) {
      std::memcpy(&value, raw.data() + 8 * i, 8);
    } else {
      std::uint16_t u;
      std::memcpy(&u, raw.data() + 2 * i, 2);
      value = u;
    }
    depth.data[i] = static_cast<float>(value * scale);
  }
  return depth;
}

void writeDepthNpy(const std::string& path, const DepthImage& depth) {
  if (depth.empty()) throw InvalidArgument(path + ": empty depth image");
  std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                     std::to_string(depth.height) + ", " + std::to_string(depth.width) + ", 1), }";
  // Pad so that magic + length + header is a multiple of 64, ending in a newline.
  const std::size_t total = ((10 + dict.size() + 1 + 63) / 64) * 64;
  dict.append(total - 10 - dict.size() - 1, ' ');
  dict.push_back('\n');
  writeFileAtomically(path, [&](std::ostream& out) {
    const unsigned char prefix[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
    out.write(reinterpret_cast<const char*>(prefix), 8);
    const unsigned char length[2] = {static_cast<unsigned char>(dict.size() & 0xff),
                                     static_cast<unsigned char>(dict.size() >> 8)};
    out.write(reinterpret_cast<const char*>(length), 2);
    out.write(dict.data(), static_cast<std::streamsize>(dict.size()));
    out.write(reinterpret_cast<const char*>(depth.data.data()),
              static_cast<std::streamsize>(depth.data.size() * sizeof(float)));
  });
}

DepthImage readDepthPng(const std::string& path, double scale) {
  pngDepthSize(path);  // type and size from the header, before the decoder allocates
  const cv::Mat image = readWithOpenCv(path, cv::IMREAD_ANYDEPTH);
  if (image.type() != CV_16UC1) throw IoError(path, "expected a 16-bit single-channel depth PNG");
  DepthImage depth(image.cols, image.rows);
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      depth.at(u, v) = static_cast<float>(image.at<std::uint16_t>(v, u) * scale);
    }
  }
  return depth;
}

DepthImage removeDepthDiscontinuities(const DepthImage& depth, int window, double max_jump_m,
                                      std::size_t* removed) {
  if (window < 3 || window % 2 == 0 || !(max_jump_m > 0)) {
    throw InvalidArgument("removeDepthDiscontinuities: window must be odd and >= 3, jump positive");
  }
  // Missing depth counts as 0, so pixels next to holes go too, as in the YCB reference scripts.
  cv::Mat z(depth.height, depth.width, CV_32FC1);
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const float d = depth.at(u, v);
      z.at<float>(v, u) = std::isfinite(d) && d > 0 ? d : 0.0f;
    }
  }
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(window, window));
  cv::Mat lo, hi;
  cv::erode(z, lo, kernel, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  cv::dilate(z, hi, kernel, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  DepthImage out = depth;
  std::size_t count = 0;
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      const float mid = z.at<float>(v, u);
      if (mid <= 0) continue;
      if (mid - lo.at<float>(v, u) > max_jump_m || hi.at<float>(v, u) - mid > max_jump_m) {
        out.at(u, v) = 0.0f;
        ++count;
      }
    }
  }
  if (removed) *removed = count;
  return out;
}

}  // namespace skelgrasp::perception
