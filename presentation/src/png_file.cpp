#include "png_file.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <vector>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::presentation::internal {

namespace {

constexpr int kBitsPerChannel = 8;
// zlib level 6: libpng's default trade-off; pictures are small and written once.
constexpr int kCompressionLevel = 6;

// libpng reports errors through a callback that must not return. It keeps the message and jumps
// back to encode() (libpng's documented setjmp protocol; no C++ exception crosses libpng's C
// frames), which throws from there.
struct PngErrorState {
  std::string message;
};

[[noreturn]] void keepPngError(png_structp png, png_const_charp message) {
  static_cast<PngErrorState*>(png_get_error_ptr(png))->message = message;
  png_longjmp(png, 1);
}

void ignorePngWarning(png_structp, png_const_charp) {}

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

void encode(const std::string& path, int width, int height, const std::uint8_t* pixels,
            std::size_t row_stride_bytes) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw IoError(path, "cannot open for writing");
  PngErrorState error;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, keepPngError, ignorePngWarning);
  if (png == nullptr) throw IoError(path, "cannot write PNG: out of memory");
  png_infop info = png_create_info_struct(png);
  struct Owner {
    png_structp* png;
    png_infop* info;
    ~Owner() { png_destroy_write_struct(png, info); }
  } owner{&png, &info};
  if (info == nullptr) throw IoError(path, "cannot write PNG: out of memory");

  // Only the png structs, the FILE and `error` live across the jump; none changes after it is set.
  if (setjmp(png_jmpbuf(png)) != 0) throw IoError(path, "cannot write PNG: " + error.message);
  png_init_io(png, file.get());
  png_set_compression_level(png, kCompressionLevel);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height),
               kBitsPerChannel, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);  // the rows are BGR; the file stores RGB
  for (int y = 0; y < height; ++y) {
    png_write_row(png, pixels + static_cast<std::size_t>(y) * row_stride_bytes);
  }
  png_write_end(png, nullptr);
  // A full disk shows at the flush: fclose's result is the last word on the file's content.
  std::FILE* raw = file.release();
  if (std::fclose(raw) != 0) throw IoError(path, "cannot write PNG: close failed");
}

}  // namespace

void writeBgrPng(const std::string& path, int width, int height, const std::uint8_t* pixels,
                 std::size_t row_stride_bytes) {
  if (width <= 0 || height <= 0 || pixels == nullptr ||
      row_stride_bytes < static_cast<std::size_t>(width) * 3) {
    throw InvalidArgument("writeBgrPng: bad image size " + std::to_string(width) + "x" +
                          std::to_string(height));
  }
  writeFileViaTemporary(path, [&](const std::string& temporary) {
    encode(temporary, width, height, pixels, row_stride_bytes);
  });
}

}  // namespace skelgrasp::presentation::internal
