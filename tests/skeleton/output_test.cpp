#include "skelgrasp/skeleton/output.h"

#include <gtest/gtest.h>

#include "skelgrasp/geometry/shapes.h"

namespace skelgrasp::skeleton {
namespace {

TEST(SkeletonOutput, JsonFollowsTheDocumentedSchema) {
  const TriangleMesh input = geometry::shapes::makeNamedShape("hammer");
  const auto r = extractSkeleton(input);
  ASSERT_TRUE(r.status.ok());
  MeshLoadInfo info;
  info.path = "hammer.ply";
  info.format = "ply";
  const auto j = skeletonToJson(r, input, info);
  EXPECT_EQ(j["schema"], "skelgrasp.skeleton/1");
  EXPECT_EQ(j["input"]["vertices"], input.numVertices());
  EXPECT_EQ(j["input"]["units"], "m");
  for (const char* key : {"method", "alpha_m", "offset_m", "input", "output"}) {
    EXPECT_TRUE(j["regularisation"].contains(key)) << key;
  }
  EXPECT_TRUE(j["regularisation"]["output"]["genus"].is_number());
  ASSERT_EQ(j["vertices"].size(), r.skeleton.vertices.size());
  std::size_t points = 0;
  for (const auto& v : j["vertices"]) {
    EXPECT_EQ(v["position"].size(), 3u);
    const std::string type = v["type"];
    EXPECT_TRUE(type == "branch" || type == "endpoint" || type == "connecting");
    EXPECT_EQ(v["segment"].is_null(), type == "branch");
    points += v["surface_points"].size();
  }
  EXPECT_EQ(points, input.numVertices());
  EXPECT_EQ(j["edges"].size(), r.skeleton.edges.size());
  for (const auto& s : j["segments"]) {
    EXPECT_EQ(s["ends"].size(), 2u);
    EXPECT_GT(s["length"].get<double>(), 0);
  }
  EXPECT_TRUE(j["timing"]["regularise_s"].is_number());
  EXPECT_TRUE(j["timing"]["skeleton_s"].is_number());
}

TEST(SkeletonOutput, SegmentationColoursFollowVertexTypes) {
  const TriangleMesh input = geometry::shapes::makeNamedShape("y_shape");
  const auto r = extractSkeleton(input);
  ASSERT_TRUE(r.status.ok());
  const TriangleMesh coloured = colourByVertexType(input, r.skeleton);
  ASSERT_EQ(coloured.vertex_colors.size(), input.numVertices());
  std::size_t red = 0, yellow = 0, blue = 0;
  for (const auto& c : coloured.vertex_colors) {
    if (c == Rgb{220, 30, 30}) ++red;
    if (c == Rgb{240, 210, 40}) ++yellow;
    if (c == Rgb{40, 80, 220}) ++blue;
  }
  EXPECT_EQ(red + yellow + blue, input.numVertices());
  EXPECT_GT(red, 0u);     // the three arm ends
  EXPECT_GT(yellow, 0u);  // the arms
  EXPECT_GT(blue, 0u);    // the junction
}

}  // namespace
}  // namespace skelgrasp::skeleton
