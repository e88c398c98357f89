#include "skelgrasp/common/mesh_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/file_header.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

class MeshIoRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshIoRoundTrip, PreservesGeometry) {
  const TriangleMesh box = geometry::shapes::makeBox({0.1, 0.2, 0.3}, 2);
  const std::string path = test::tempDir("io_" + GetParam()) + "/box." + GetParam();
  saveMesh(path, box);
  MeshLoadInfo info;
  const TriangleMesh loaded = loadMesh(path, {}, &info);
  EXPECT_EQ(info.format, GetParam());
  EXPECT_EQ(loaded.numFaces(), box.numFaces());
  // STL is a soup and is welded by position; the others keep vertex order exactly.
  ASSERT_EQ(loaded.numVertices(), box.numVertices());
  if (GetParam() != "stl") {
    for (std::size_t i = 0; i < box.numVertices(); ++i) {
      EXPECT_LT((loaded.vertices[i] - box.vertices[i]).norm(), 1e-6);
    }
  }
  EXPECT_NEAR(loaded.signedVolume(), box.signedVolume(), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshIoRoundTrip, ::testing::Values("ply", "obj", "off", "stl"));

TEST(MeshIo, PlyKeepsVertexColours) {
  TriangleMesh mesh = geometry::shapes::makeBox({1, 1, 1});
  mesh.scale(0.1);
  mesh.vertex_colors.assign(mesh.numVertices(), Rgb{10, 20, 30});
  const std::string path = test::tempDir("io_colour") + "/c.ply";
  saveMesh(path, mesh);
  std::ifstream in(path, std::ios::binary);
  std::string header((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  EXPECT_EQ(loadMesh(path).numVertices(), mesh.numVertices());
}

TEST(MeshIo, ExtraUcharVertexPropertiesRoundTripInVertexOrder) {
  TriangleMesh mesh = geometry::shapes::makeSphere(0.05, 16, 8);
  mesh.vertex_colors.assign(mesh.numVertices(), Rgb{1, 2, 3});
  std::vector<std::uint8_t> observed(mesh.numVertices()), parity(mesh.numVertices());
  for (std::size_t i = 0; i < observed.size(); ++i) {
    observed[i] = mesh.vertices[i].z() > 0 ? 1 : 0;  // a pattern tied to the vertex order
    parity[i] = static_cast<std::uint8_t>(i % 7);
  }
  const std::string path = test::tempDir("io_props") + "/flags.ply";
  saveMesh(path, mesh, {{"observed", observed}, {"parity", parity}});

  const TriangleMesh loaded = loadMesh(path);  // readers that ignore the properties still work
  ASSERT_EQ(loaded.numVertices(), mesh.numVertices());
  EXPECT_LT((loaded.vertices[5] - mesh.vertices[5]).norm(), 1e-6);
  EXPECT_EQ(loadPlyVertexProperty(path, "observed"), observed);
  EXPECT_EQ(loadPlyVertexProperty(path, "parity"), parity);
  EXPECT_THROW(loadPlyVertexProperty(path, "missing"), IoError);
}

TEST(MeshIo, ExtraVertexPropertiesAreValidated) {
  const TriangleMesh mesh = geometry::shapes::makeBox({0.1, 0.1, 0.1});
  const std::string dir = test::tempDir("io_props_bad");
  const std::vector<std::uint8_t> short_values(mesh.numVertices() - 1, 1);
  const std::vector<std::uint8_t> values(mesh.numVertices(), 1);
  EXPECT_THROW(saveMesh(dir + "/a.ply", mesh, {{"observed", short_values}}), InvalidArgument);
  EXPECT_THROW(saveMesh(dir + "/a.ply", mesh, {{"bad name", values}}), InvalidArgument);
  EXPECT_THROW(saveMesh(dir + "/a.obj", mesh, {{"observed", values}}), InvalidArgument);
}

TEST(MeshIo, BoundsSkipNonFinitePoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto box = boundingBox({{0, 0, 0}, {nan, nan, nan}, {1, 2, 3}});
  EXPECT_EQ(box.max, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(box.min, Eigen::Vector3d(0, 0, 0));
}

TEST(MeshIo, MillimetreInputIsDetectedAndScaled) {
  TriangleMesh mesh = geometry::shapes::makeBox({80, 60, 120});  // a box in mm
  const std::string path = test::tempDir("io_mm") + "/mm.obj";
  saveMesh(path, mesh);
  MeshLoadInfo info;
  const TriangleMesh auto_loaded = loadMesh(path, {}, &info);
  EXPECT_TRUE(info.units_guessed);
  EXPECT_DOUBLE_EQ(info.scale_to_meters, 1e-3);
  EXPECT_NEAR(auto_loaded.bounds().extent().z(), 0.12, 1e-9);
  MeshLoadOptions keep;
  keep.units = LengthUnit::kMeters;
  EXPECT_NEAR(loadMesh(path, keep).bounds().extent().z(), 120, 1e-9);
  MeshLoadOptions mm;
  mm.units = LengthUnit::kMillimeters;
  EXPECT_NEAR(loadMesh(path, mm).bounds().extent().z(), 0.12, 1e-9);
}

TEST(MeshIo, QuadsAreTriangulated) {
  const std::string path = test::tempDir("io_quad") + "/quad.off";
  writeText(path, "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  MeshLoadInfo info;
  const TriangleMesh mesh = loadMesh(path, {}, &info);
  EXPECT_EQ(mesh.numFaces(), 2u);
  EXPECT_EQ(info.polygons_triangulated, 1u);
}

// Each bad input raises IoError whose message names the file and the problem.
struct BadInput {
  std::string name;
  std::string file;
  std::string content;  // empty: the file is not created
  std::string expected_problem;
};

class MeshIoBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(MeshIoBadInput, ThrowsIoErrorNamingFileAndProblem) {
  const auto& c = GetParam();
  const std::string path = test::tempDir("bad_" + c.name) + "/" + c.file;
  if (!c.content.empty()) writeText(path, c.content);
  if (c.name == "empty_file") writeText(path, "");
  try {
    loadMesh(path);
    FAIL() << "expected IoError for " << c.name;
  } catch (const IoError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(e.problem().find(c.expected_problem), std::string::npos) << e.problem();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MeshIoBadInput,
    ::testing::Values(
        BadInput{"missing", "nothing.ply", "", "no such file"},
        BadInput{"unknown_format", "mesh.xyz", "1 2 3\n", "unknown mesh format"},
        BadInput{"empty_file", "empty.obj", "", "file is empty"},
        BadInput{"garbage_ply", "garbage.ply", "this is not a ply file\n", "not a PLY file"},
        BadInput{"no_faces", "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
        BadInput{"nan", "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"},
        BadInput{"index_out_of_range", "bad_index.off",
                 "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "index out of range"},
        // Strict files (issue 13): required properties, index signs, declared counts.
        BadInput{"ply_without_z", "flat.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0\n1 0\n0 1\n3 0 1 2\n",
                 "PLY vertex element has no 'z' property"},
        // CGAL reads coordinates only as float or double (fuzz/regressions/mesh_reader/
        // ply_integer_coordinate).
        BadInput{"ply_integer_coordinate", "int_z.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property uint8 z\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 "PLY vertex property 'z' is of type uint8, expected float or double"},
        // CGAL reads every element of a name (fuzz/regressions/mesh_reader/
        // ply_second_vertex_element).
        BadInput{"ply_vertex_element_twice", "two_vertex.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                 "property float z\nelement vertex 1\nproperty uint8 x\nend_header\n0 0 0\n0\n",
                 "element 'vertex' declared twice"},
        BadInput{"ply_property_twice", "two_x.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                 "property float z\nproperty uint8 x\nend_header\n0 0 0 0\n",
                 "property 'x' declared twice in element 'vertex'"},
        BadInput{"ply_without_face_indices", "faces.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty uchar flags\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n7\n",
                 "no 'vertex_indices' list property"},
        BadInput{"ply_negative_index", "negative.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -7\n",
                 "face 0 has a negative vertex index (-7)"},
        // CGAL converts OFF indices from floating point (fuzz/regressions/mesh_reader/
        // off_face_index_1e62); faces may start on the header's line.
        BadInput{"off_index_beyond_integers", "huge.off",
                 "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999999999\n",
                 "face 0 has a vertex index that is not an integer"},
        BadInput{"off_fractional_index", "fraction.off",
                 "OFF 3 1 0 0 0 0\n1 0 0\n0 1 0\n3 0 1 1.5\n",
                 "face 0 has a vertex index that is not an integer ('1.5')"},
        BadInput{"off_face_on_header_line", "inline.off", "OFF 1 1 0 0 0 0\n3 0 0 0\n",
                 "face 0 has 3 corners, but the file has only 1 vertices"},
        BadInput{"off_edge_count_runs_into_a_face", "edges.off", "OFF 0 1\n\n00-10 1\n",
                 "OFF header: the edge count is not a whole number ('00-10')"},
        // CGAL doubles the edge count in an int (fuzz/regressions/mesh_reader/
        // off_edge_count_1700413616).
        BadInput{"off_edge_count_overflows", "edges_overflow.off", "OFF 1 0\n1700413616\n0 0 0\n",
                 "OFF header: the edge count 1700413616 is too large (at most 1073741823)"},
        // CGAL sizes a face by its corner count first (fuzz/regressions/mesh_reader/
        // off_face_with_385e6_corners).
        BadInput{"off_more_corners_than_vertices", "corners.off",
                 "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n385206008 0 1 2\n",
                 "face 0 has 385206008 corners, but the file has only 3 vertices"},
        BadInput{"off_negative_index", "negative.off",
                 "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -7 1\n", "negative vertex index (-7)"},
        BadInput{"obj_relative_index_before_first", "relative.obj",
                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n",
                 "relative (negative) vertex index reaching before the first vertex"},
        BadInput{"ply_index_out_of_range", "beyond.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                 "face 0 references vertex 7, but the file has only 3 vertices"},
        BadInput{"ply_binary_declares_more_than_file", "huge_binary.ply",
                 "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n"
                 "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                 "property list uchar int vertex_indices\nend_header\n" +
                     std::string(64, '\x01'),
                 "declares 1000000000 'vertex' elements, which need at least 12000000000 bytes"},
        BadInput{"ply_ascii_declares_more_than_file", "huge_ascii.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 2000000000\n"
                 "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                 "3 0 1 2\n",
                 "declares 2000000000 'face' elements"},
        BadInput{"ply_negative_count", "negative_count.ply",
                 "ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n",
                 "count of element 'vertex' is negative (-3)"},
        BadInput{"off_declares_more_than_file", "huge.off",
                 "OFF\n1000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 "OFF header declares 1000000000 vertices"},
        BadInput{"off_negative_count", "negative_count.off", "OFF\n3 -1 0\n0 0 0\n1 0 0\n0 1 0\n",
                 "face count is negative (-1)"},
        // CGAL's OFF reader reads uninitialised memory on such a magic word (fuzz/regressions).
        BadInput{"off_bad_magic", "magic.off", std::string("OFF\xc4\x31\x30\x30\n0 0 0\n"),
                 "OFF header: the file must start with OFF (or COFF, NOFF, ...), not 'OFF?100'"},
        BadInput{
            "stl_declares_more_than_file", "huge.stl",
            std::string(80, 'b') + std::string("\xff\xff\xff\x0f", 4) + std::string(100, '\x01'),
            "binary STL declares 268435455 triangles"}),
    [](const auto& info) { return info.param.name; });

TEST(MeshIo, RealMeshesKeepTheirVertexCounts) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  const std::string root = test::sharedDataDir() + "/objects/";
  // Counts from the data's SOURCES.md.
  EXPECT_EQ(loadMesh(root + "ycb/002_master_chef_can.ply").numVertices(), 8006u);
  EXPECT_EQ(loadMesh(root + "ycb/025_mug.ply").numFaces(), 16384u);
  EXPECT_EQ(loadMesh(root + "kit/Amicelli_800_tex.obj").numVertices(), 400u);
  EXPECT_EQ(loadMesh(root + "ycb_poisson_simox/pringles-poisson_mesh2.stl").numVertices(), 14531u);
  EXPECT_EQ(loadMesh(root + "ycb_poisson_simox/pringles-poisson_mesh3.stl").numVertices(), 2779u);
}

// The header checks (required properties, declared counts against file size) accept every mesh
// of the shared data: strictness must not cost a real file.
TEST(MeshIo, EveryRealMeshPassesTheHeaderChecks) {
  SKELGRASP_REQUIRE_SHARED_DATA();
  std::size_t checked = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(test::sharedDataDir() + "/objects")) {
    const std::string ext = fileExtension(entry.path().string());
    if (ext != "ply" && ext != "off" && ext != "stl" && ext != "obj") continue;
    EXPECT_NO_THROW(checkMeshFileHeader(entry.path().string(), ext)) << entry.path();
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

}  // namespace
}  // namespace skelgrasp
