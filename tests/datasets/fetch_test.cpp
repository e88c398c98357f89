#include "skelgrasp/datasets/fetch.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/datasets/ycb_raw.h"
#include "skelgrasp/datasets/ycb_raw_fixture.h"
#include "test_support.h"

namespace skelgrasp::datasets {
namespace {

namespace fs = std::filesystem;

TEST(Fetch, BuildsTheOfficialArchiveUrls) {
  EXPECT_EQ(ycbRgbdArchiveUrl("003_cracker_box"),
            "http://ycb-benchmarks.s3-website-us-east-1.amazonaws.com/data/berkeley/"
            "003_cracker_box/003_cracker_box_berkeley_rgbd.tgz");
  EXPECT_EQ(ycbRgbdArchiveUrl("065-a_cups", "file:///data/mirror/"),
            "file:///data/mirror/065-a_cups/065-a_cups_berkeley_rgbd.tgz");
  for (const std::string id : {"003_cracker_box", "065-a_cups", "072-b_toy_airplane"}) {
    EXPECT_TRUE(isValidYcbId(id)) << id;
  }
  for (const std::string id : {"", "3_box", "003", "003_", "../003_box", "003_Box", "003_box/x",
                               "003_box;rm", "003-ab_box"}) {
    EXPECT_FALSE(isValidYcbId(id)) << id;
    EXPECT_THROW(ycbRgbdArchiveUrl(id), InvalidArgument) << id;
  }
  EXPECT_THROW(ycbRgbdArchiveUrl("003_cracker_box", "/"), InvalidArgument);
}

// A local mirror holding "<id>/<id>_berkeley_rgbd.tgz" made from the fixture with the system tar,
// laid out like the official server; the download goes through libcurl's file:// support.
TEST(Fetch, DownloadsAndUnpacksFromALocalMirror) {
  const std::string root = test::tempDir("fetch");
  const std::string id = "000_test_cylinder";
  YcbRawFixtureSpec spec;
  spec.angles = {0, 180};
  writeYcbRawFixture(root + "/staging/" + id, spec);
  fs::create_directories(root + "/mirror/" + id);
  const std::string archive = root + "/mirror/" + id + "/" + id + "_berkeley_rgbd.tgz";
  const std::string tar = "tar -czf " + archive + " -C " + root + "/staging " + id;
  ASSERT_EQ(std::system(tar.c_str()), 0);

  const auto results = fetchYcbRgbd({id}, root + "/ycb", "file://" + root + "/mirror");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].folder, root + "/ycb/" + id + "_berkeley_rgbd/" + id);
  EXPECT_TRUE(fs::exists(results[0].folder + "/calibration.h5"));
  EXPECT_FALSE(fs::exists(results[0].archive));  // removed after unpacking
  EXPECT_FALSE(fs::exists(results[0].archive + ".part"));
  YcbRawParams p;
  EXPECT_EQ(loadYcbRaw(results[0].folder, p).views.size(), 6u);
}

TEST(Fetch, FailuresNameTheUrlOrArchive) {
  const std::string root = test::tempDir("fetch_bad");
  try {
    downloadFile("file://" + root + "/nothing.tgz", root + "/out.tgz");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.tgz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("download failed"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(root + "/out.tgz"));
  EXPECT_FALSE(fs::exists(root + "/out.tgz.part"));
  std::ofstream(root + "/garbage.tgz") << "this is not gzip";
  try {
    unpackTarGz(root + "/garbage.tgz", root + "/unpacked");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("tar failed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(unpackTarGz(root + "/absent.tgz", root + "/unpacked"), IoError);
  EXPECT_THROW(fetchYcbRgbd({"003_cracker_box", "bad id"}, root), InvalidArgument);
}

}  // namespace
}  // namespace skelgrasp::datasets
