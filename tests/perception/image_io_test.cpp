#include "skelgrasp/perception/image_io.h"

#include <gtest/gtest.h>

#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/perception/rgbd.h"
#include "test_support.h"

namespace skelgrasp::perception {
namespace {

TEST(ImageIo, NpyDepthRoundTripsAndReadsOtherDtypes) {
  DepthImage depth(5, 3);
  for (std::size_t i = 0; i < depth.data.size(); ++i) depth.data[i] = 0.5f + 0.01f * i;
  const std::string dir = test::tempDir("npy");
  writeDepthNpy(dir + "/d.npy", depth);
  const DepthImage back = readDepthNpy(dir + "/d.npy");
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  EXPECT_EQ(back.data, depth.data);
  EXPECT_FLOAT_EQ(readDepthNpy(dir + "/d.npy", 1000.0).at(4, 2), 1000.0f * depth.at(4, 2));

  // uint16 millimetres, shape (2, 2), version 1.0 header written by hand.
  std::string dict = "{'descr': '<u2', 'fortran_order': False, 'shape': (2, 2), }";
  dict.append(128 - 10 - dict.size() - 1, ' ');
  dict.push_back('\n');
  std::ofstream out(dir + "/mm.npy", std::ios::binary);
  out << "\x93NUMPY" << '\x01' << '\x00' << static_cast<char>(dict.size()) << '\x00' << dict;
  const std::uint16_t values[4] = {500, 750, 0, 1234};
  out.write(reinterpret_cast<const char*>(values), sizeof(values));
  out.close();
  const DepthImage mm = readDepthNpy(dir + "/mm.npy", 0.001);
  EXPECT_FLOAT_EQ(mm.at(1, 0), 0.75f);
  EXPECT_FLOAT_EQ(mm.at(0, 1), 0.0f);
}

TEST(ImageIo, BadNpyFilesNameTheProblem) {
  const std::string dir = test::tempDir("npy_bad");
  std::ofstream(dir + "/text.npy") << "not numpy at all";
  EXPECT_THROW(readDepthNpy(dir + "/text.npy"), IoError);
  DepthImage depth(4, 4, 1.0f);
  writeDepthNpy(dir + "/ok.npy", depth);
  std::ifstream in(dir + "/ok.npy", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(dir + "/short.npy", std::ios::binary) << bytes.substr(0, bytes.size() - 10);
  try {
    readDepthNpy(dir + "/short.npy");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(e.problem().find("truncated"), std::string::npos) << e.problem();
  }
  EXPECT_THROW(readDepthNpy(dir + "/none.npy"), IoError);
}

// A version 1.0 .npy file with header `dict` followed by `data_bytes` zero bytes.
void writeNpy(const std::string& path, std::string dict, std::size_t data_bytes) {
  dict.append(128 - 10 - dict.size() - 1, ' ');
  dict.push_back('\n');
  std::ofstream out(path, std::ios::binary);
  out << "\x93NUMPY" << '\x01' << '\x00' << static_cast<char>(dict.size()) << '\x00' << dict;
  out << std::string(data_bytes, '\0');
}

// Shapes are checked against overflow and the file size before anything is allocated, and the
// error names the file (issue 13: a huge shape used to say "cannot create std::vector larger
// than max_size()").
TEST(ImageIo, NpyShapesLargerThanTheFileNameTheFile) {
  const std::string dir = test::tempDir("npy_shapes");
  struct Case {
    std::string name, shape, expected;
  };
  for (const Case& c : {
           Case{"overflow", "(99999999999999999999, 5)", ".npy shape dimension is too large"},
           // Sides beyond kMaxImageSidePx are refused before the file's length is looked at
           // (a sparse file may hold them).
           Case{"huge", "(4000000000, 4000000000)", "exceeds the largest image side of 20000"},
           Case{"beyond_cap", "(30000, 30000)", "exceeds the largest image side of 20000"},
           Case{"beyond_file", "(10000, 10000)",
                "shape (10000, 10000) of '<f4' needs 400000000 bytes, the file holds 16"},
           Case{"negative", "(-4, 4)", ".npy shape dimension is negative (-4)"},
       }) {
    const std::string path = dir + "/" + c.name + ".npy";
    writeNpy(path, "{'descr': '<f4', 'fortran_order': False, 'shape': " + c.shape + ", }", 16);
    try {
      readDepthNpy(path);
      ADD_FAILURE() << c.name << ": expected IoError";
    } catch (const IoError& e) {
      EXPECT_EQ(e.path(), path);
      EXPECT_NE(e.problem().find(c.expected), std::string::npos) << c.name << ": " << e.problem();
    }
  }
  // A version 2.0 header length of 4 GiB in a 16-byte file.
  const std::string path = dir + "/long_header.npy";
  std::ofstream(path, std::ios::binary)
      << "\x93NUMPY" << '\x02' << '\x00' << std::string("\xff\xff\xff\xff", 4) << "{'descr'";
  try {
    readDepthNpy(path);
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(e.problem().find("truncated .npy header"), std::string::npos) << e.problem();
  }
}

TEST(ImageIo, MasksRoundTripThroughPngAndPbm) {
  MaskImage mask(9, 7, 0);
  for (int v = 2; v < 5; ++v) {
    for (int u = 3; u < 8; ++u) mask.at(u, v) = 255;
  }
  const std::string dir = test::tempDir("masks");
  for (const std::string ext : {"png", "pbm"}) {
    writeMaskImage(dir + "/m." + ext, mask);
    EXPECT_EQ(readMaskImage(dir + "/m." + ext).data, mask.data) << ext;
  }
  // PBM stores black as bit 1: a mask written with object pixels 0 (YCB convention) has its
  // object pixels set in the file.
  std::ifstream in(dir + "/m.pbm", std::ios::binary);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "P4");
  EXPECT_THROW(readMaskImage(dir + "/absent.png"), IoError);
  std::ofstream(dir + "/broken.png") << "PNG? no";
  EXPECT_THROW(readMaskImage(dir + "/broken.png"), IoError);
}

TEST(ImageIo, DiscontinuitiesAroundAStepAreRemoved) {
  DepthImage depth(20, 10, 1.0f);
  for (int v = 0; v < 10; ++v) {
    for (int u = 10; u < 20; ++u) depth.at(u, v) = 0.6f;  // a 0.4 m step at u = 10
  }
  std::size_t removed = 0;
  const DepthImage out = removeDepthDiscontinuities(depth, 7, 0.1, &removed);
  EXPECT_EQ(out.at(0, 5), 1.0f);
  EXPECT_EQ(out.at(19, 5), 0.6f);
  EXPECT_EQ(out.at(9, 5), 0.0f);
  EXPECT_EQ(out.at(10, 5), 0.0f);
  EXPECT_EQ(removed, 6u * 10u);  // three columns either side of the step
  EXPECT_THROW(removeDepthDiscontinuities(depth, 4, 0.1), InvalidArgument);
}

TEST(ImageIo, ReadsThePrimesenseCaptures) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string dir = test::sharedDataDir() + "/captures/gqcnn_primesense/";
  const DepthImage depth = readDepthNpy(dir + "00_flashlight/depth_0.npy");
  ASSERT_EQ(depth.width, 640);
  ASSERT_EQ(depth.height, 480);
  const auto [lo, hi] = std::minmax_element(depth.data.begin(), depth.data.end());
  EXPECT_NEAR(*lo, 0.538, 0.001);  // SOURCES.md: range 0.538-0.817 m over all captures
  EXPECT_LE(*hi, 0.818f);
  const MaskImage mask = readMaskImage(dir + "00_flashlight/segmask_0.png");
  EXPECT_EQ(mask.width, 640);
  const auto object = std::count_if(mask.data.begin(), mask.data.end(), [](auto m) { return m; });
  EXPECT_GE(object, 1574);  // SOURCES.md: 1574-5229 object pixels per capture
  EXPECT_LE(object, 5229);
}

}  // namespace
}  // namespace skelgrasp::perception
