// The demo report's 3D view as a reader sees it: headless Chromium opens the page from disk (no
// network), the viewer reports success, no JavaScript error is logged, and a screenshot of the
// view shows the object in its skeleton-segment colours.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_support.h"
#include "skelgrasp/perception/image_io.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

using test::runCli;

// The palette skeleton::colourBySegment gives segments (skeleton/src/output.cpp).
const Rgb kSegmentPalette[] = {{230, 25, 75},  {60, 180, 75},   {255, 225, 25}, {0, 130, 200},
                               {245, 130, 48}, {145, 30, 180},  {70, 240, 240}, {240, 50, 230},
                               {210, 245, 60}, {250, 190, 212}, {0, 128, 128},  {170, 110, 40}};
// A lit pixel is the colour times a brightness factor (ambient 0.55 + directional 0.6 × cosine);
// it matches a palette colour when it is that colour scaled by a factor in this range, within
// this many grey levels.
constexpr double kMinBrightness = 0.4, kMaxBrightness = 1.25, kResidualLevels = 10;
constexpr int kWindowWidth = 1000, kWindowHeight = 900;
// The demo report's size budget (docs/report.md).
constexpr std::uintmax_t kReportBudgetBytes = 5u << 20;

bool matchesPalette(const Rgb& p) {
  const Eigen::Vector3d pixel(p[0], p[1], p[2]);
  for (const auto& c : kSegmentPalette) {
    const Eigen::Vector3d colour(c[0], c[1], c[2]);
    const double k = pixel.dot(colour) / colour.squaredNorm();
    if (k < kMinBrightness || k > kMaxBrightness) continue;
    if ((pixel - k * colour).cwiseAbs().maxCoeff() <= kResidualLevels) return true;
  }
  return false;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

std::string chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    if (std::system((std::string("command -v ") + name + " > /dev/null 2>&1").c_str()) == 0)
      return name;
  }
  return {};
}

// Headless Chromium with software WebGL (SwiftShader), as on a machine without a GPU.
std::string browserCommand(const std::string& browser, const std::string& dir) {
  return browser + " --headless --no-sandbox --disable-gpu --use-angle=swiftshader" +
         " --enable-unsafe-swiftshader --no-first-run --user-data-dir=" + dir + "/profile" +
         " --enable-logging=stderr --v=0 --virtual-time-budget=8000" +
         " --window-size=" + std::to_string(kWindowWidth) + "," + std::to_string(kWindowHeight);
}

TEST(Report3d, TheDemoReportShowsAWorking3dViewInABrowser) {
  const std::string browser = chromium();
  if (browser.empty()) {
    GTEST_SKIP() << "Chromium not installed (Debian package `chromium`; "
                    "scripts/install-deps.sh --test installs it)";
  }
  const std::string dir = test::tempDir("report3d_browser");
  const auto demo = runCli("demo --out " + dir + "/demo", dir);
  ASSERT_EQ(demo.exit_code, 0) << demo.err;
  // The demo is one `run --object all`: one report with the whole scene in 3D.
  const std::string report = dir + "/demo/report.html";
  ASSERT_TRUE(std::filesystem::exists(report));
  // Self-contained: no script is fetched, and the page stays within its budget.
  const std::string html = slurp(report);
  EXPECT_EQ(html.find("<script src="), std::string::npos);
  EXPECT_NE(html.find("id=\"sv3d\""), std::string::npos);
  EXPECT_LE(std::filesystem::file_size(report), kReportBudgetBytes);

  const std::string url = "file://" + report;
  const std::string base = browserCommand(browser, dir);
  ASSERT_EQ(
      std::system(
          (base + " --dump-dom " + url + " > " + dir + "/dom.html 2> " + dir + "/dom.log").c_str()),
      0);
  const std::string dom = slurp(dir + "/dom.html");
  EXPECT_NE(dom.find("data-status=\"ok\""), std::string::npos)
      << "the viewer did not report success: " << dom.substr(dom.find("id=\"sv3d\""), 200);
  const std::string log = slurp(dir + "/dom.log");
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;

  const std::string png = dir + "/view.png";
  ASSERT_EQ(
      std::system(
          (base + " --screenshot=" + png + " " + url + " > " + dir + "/shot.log 2>&1").c_str()),
      0);
  const auto image = perception::readColorImage(png);
  ASSERT_EQ(image.width, kWindowWidth);
  // The view is the page's first block below the title; count its pixels in segment colours and
  // those that are not the canvas background.
  int segment_pixels = 0, drawn_pixels = 0;
  const Rgb background{0xf4, 0xf4, 0xf6};
  for (int v = 150; v < 650; ++v) {
    for (int u = 20; u < kWindowWidth - 40; ++u) {
      const Rgb& p = image.at(u, v);
      if (p != background && p != Rgb{255, 255, 255}) ++drawn_pixels;
      if (matchesPalette(p)) ++segment_pixels;
    }
  }
  EXPECT_GT(drawn_pixels, 5000) << "the 3D view looks blank";
  EXPECT_GT(segment_pixels, 300) << "the objects' segment colours are not visible";
}

}  // namespace
}  // namespace skelgrasp
