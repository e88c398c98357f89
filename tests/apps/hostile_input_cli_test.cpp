// Hostile input, round three (issue 77): degenerate meshes, capture intrinsics, oversized images,
// hand files and grasps files. Each ends with exit 2, one error line naming the file and the
// problem, and nothing written.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "cli_support.h"
#include "hostile_files.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/geometry/shapes.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "test_support.h"

namespace skelgrasp {
namespace {

namespace fs = std::filesystem;
using test::BadCliInput;
using test::CliRun;
using test::countLines;
using test::lastLine;
using test::runCli;
using test::validGrasps;
using test::withDir;
using test::writeText;

// The single face of this mesh has zero area: its corners lie on one line.
const char* const kCollinearPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n0.05 0 0\n0.1 0 0\n3 0 1 2\n";

// A file of `bytes` bytes that takes no disk space (a hole): the readers must refuse it by size.
void writeSparse(const std::string& path, std::uintmax_t bytes) {
  std::ofstream(path, std::ios::binary).close();
  fs::resize_file(path, bytes);
}

// NumPy .npy v1.0 of little-endian float32 with the given shape text and `values` floats of data.
std::string npyBytes(const std::string& shape, std::size_t values) {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  const float depth = 0.5f;
  for (std::size_t i = 0; i < values; ++i)
    bytes.append(reinterpret_cast<const char*>(&depth), sizeof depth);
  return bytes;
}

// The signature and IHDR of a PNG declaring `width` x `height` pixels of `bits`-bit colour type
// `colour_type`, and nothing after: the readers must refuse it from the header alone.
std::string pngHeader(std::uint32_t width, std::uint32_t height, int bits, int colour_type) {
  std::string bytes("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) bytes += static_cast<char>((v >> shift) & 0xff);
  bytes += static_cast<char>(bits);
  bytes += static_cast<char>(colour_type);
  bytes += std::string("\0\0\0\0\0\0\0", 7);  // compression, filter, interlace, CRC
  return bytes;
}

std::string captureJson(const std::string& depth, const std::string& intrinsics) {
  return R"({"depth": ")" + depth + R"(", "intrinsics": )" + intrinsics + "}";
}

// Capture descriptions with hostile intrinsics or images.
void writeCaptures(const std::string& dir) {
  writeText(dir + "/depth.npy", npyBytes("(2, 2)", 4));
  const std::string vga = R"({"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5, "width": 640,
                              "height": 480})";
  const std::string two = R"({"fx": 500, "fy": 500, "cx": 1, "cy": 1, "width": 2, "height": 2})";
  writeText(dir + "/cx_inline.json",
            captureJson("depth.npy", R"({"fx": 500, "fy": 500, "cx": 1e308, "cy": 1,
                                         "width": 2, "height": 2})"));
  writeText(dir + "/cam.intr", R"({"_fx": 500, "_fy": 500, "_cx": 1e308, "_cy": 1, "_width": 2,
                                   "_height": 2})");
  writeText(dir + "/cx_file.json", captureJson("depth.npy", R"("cam.intr")"));
  writeText(dir + "/fx_huge.json",
            captureJson("depth.npy", R"({"fx": 1e308, "fy": 500, "cx": 1, "cy": 1, "width": 2,
                                         "height": 2})"));
  writeText(dir + "/width_fraction.json",
            captureJson("depth.npy", R"({"fx": 500, "fy": 500, "cx": 1, "cy": 1, "width": 640.5,
                                         "height": 2})"));
  writeText(dir + "/mismatch.json", captureJson("depth.npy", vga));
  writeText(dir + "/huge.png", pngHeader(30000, 30000, 16, 0));
  writeText(dir + "/huge_png.json", captureJson("huge.png", vga));
  writeText(dir + "/rgb16.png", pngHeader(2, 2, 16, 2));
  writeText(dir + "/rgb16.json", captureJson("rgb16.png", two));
  // An 8-bit mask PNG cut after its header: libpng's own complaint must not add a line.
  writeText(dir + "/mask_truncated.png", pngHeader(2, 2, 8, 0) + std::string(8, '\x78'));
  writeText(dir + "/mask_truncated.json",
            R"({"depth": "depth.npy", "mask": "mask_truncated.png", "intrinsics": )" + two + "}");
  writeText(dir + "/mask16.png", pngHeader(2, 2, 16, 0));
  writeText(dir + "/mask16.json",
            R"({"depth": "depth.npy", "mask": "mask16.png", "intrinsics": )" + two + "}");
  writeText(dir + "/huge.npy", npyBytes("(30000, 30000)", 4));
  writeText(dir + "/huge_npy.json", captureJson("huge.npy", vga));
}

// Hand files: devices, oversized files, too many links, an oversized link mesh.
void writeHands(const std::string& dir) {
  const auto gripper = grasping::builtinHandFiles("parallel_gripper");
  writeText(dir + "/gripper.urdf", gripper.urdf);
  writeText(dir + "/gripper.json", gripper.description);
  fs::create_symlink("/dev/zero", dir + "/zero.urdf");
  fs::create_symlink("/dev/zero", dir + "/zero.json");
  writeSparse(dir + "/big.urdf", (8u << 20) + 1);
  std::string links = "<robot name=\"many\">\n";
  for (int i = 0; i <= 1000; ++i) links += "<link name=\"l" + std::to_string(i) + "\"/>\n";
  writeText(dir + "/links.urdf", links + "</robot>\n");
  writeText(dir + "/mesh.urdf",
            "<robot name=\"m\"><link name=\"base\"><collision><geometry><mesh "
            "filename=\"big.stl\"/></geometry></collision></link></robot>\n");
  writeSparse(dir + "/big.stl", (16u << 20) + 1);
  // Joint j3 gives link b a second parent: a loop urdfdom lets through.
  const std::string limit = R"(<limit lower="0" upper="1" effort="1" velocity="1"/>)";
  std::string loop = "<robot name=\"loop\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>";
  for (const auto& [joint, parent, child] :
       {std::array<const char*, 3>{"j1", "a", "b"}, {"j2", "b", "c"}, {"j3", "c", "b"}}) {
    loop += std::string("<joint name=\"") + joint + "\" type=\"revolute\"><parent link=\"" +
            parent + "\"/><child link=\"" + child + "\"/>" + limit + "</joint>";
  }
  writeText(dir + "/loop.urdf", loop + "</robot>\n");
  // A two-finger hand whose values the cases below make meaningless one at a time.
  const std::string hand =
      R"(<robot name="h"><link name="base"><collision><geometry><box size="0.1 0.1 0.1"/>)"
      R"(</geometry></collision></link>)"
      R"(<link name="f"><collision><geometry><box size="0.02 0.02 0.05"/></geometry></collision>)"
      R"(</link><link name="g"><collision><geometry><box size="0.02 0.02 0.05"/></geometry>)"
      R"(</collision></link>)"
      R"(<joint name="j" type="revolute"><parent link="base"/><child link="f"/>)"
      R"(<origin xyz="0 0 0.1"/><axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" )"
      R"(velocity="1"/></joint>)"
      R"(<joint name="k" type="revolute"><parent link="base"/><child link="g"/>)"
      R"(<origin xyz="0 0.05 0.1"/><axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" )"
      R"(velocity="1"/></joint></robot>)";
  const auto variant = [&](const std::string& name, const std::string& from,
                           const std::string& to) {
    std::string text = hand;
    text.replace(text.find(from), from.size(), to);
    writeText(dir + "/" + name + ".urdf", text);
  };
  variant("box_size_zero", R"(<box size="0.02 0.02 0.05"/>)", R"(<box size="0 0.02 0.05"/>)");
  variant("mesh_scale_1e30", R"(<box size="0.02 0.02 0.05"/>)",
          R"(<mesh filename="finger.stl" scale="1e30 1e30 1e30"/>)");
  variant("joint_origin_1e308", R"(<origin xyz="0 0 0.1"/>)", R"(<origin xyz="0 0 1e308"/>)");
  variant("self_mimic", R"(<axis xyz="1 0 0"/>)", R"(<axis xyz="1 0 0"/><mimic joint="j"/>)");
  {
    std::string cycle = hand;
    for (const auto& [axis_at, leader] : {std::pair{0, "k"}, std::pair{1, "j"}}) {
      std::size_t at = cycle.find(R"(<axis xyz="1 0 0"/>)");
      if (axis_at == 1) at = cycle.find(R"(<axis xyz="1 0 0"/>)", at + 1);
      cycle.insert(at, std::string(R"(<mimic joint=")") + leader + R"("/>)");
    }
    writeText(dir + "/mimic_cycle.urdf", cycle);
  }
  // Grasp descriptions of the gripper with one meaningless value each.
  const auto description = [&](const std::string& name, const auto& change) {
    nlohmann::json d = nlohmann::json::parse(gripper.description);
    change(d);
    writeText(dir + "/" + name + ".json", d.dump());
  };
  using J = nlohmann::json;
  description("step_1e-300", [](J& d) { d["closing"]["step_m"] = 1e-300; });
  description("torsional_1e308", [](J& d) { d["closing"]["torsional_friction_m"] = 1e308; });
  description("gcp_zero_quaternion", [](J& d) {
    d["preshapes"]["power"]["gcp"]["quaternion_wxyz"] = {0, 0, 0, 0};
  });
  description("one_joint_two_fingers",
              [](J& d) { d["fingers"][1]["joints"] = d["fingers"][0]["joints"]; });
  nlohmann::json any_base = nlohmann::json::parse(gripper.description);
  any_base.erase("base_link");
  writeText(dir + "/any_base.json", any_base.dump());
}

// Grasps files with one hostile value each, named after it.
void writeGraspsFiles(const std::string& dir) {
  const nlohmann::json valid = validGrasps();
  writeJsonFile(dir + "/valid.json", valid);
  const auto variant = [&](const std::string& name, const auto& change) {
    nlohmann::json file = valid;
    change(file, file["grasps"][0]);
    writeJsonFile(dir + "/" + name + ".json", file);
  };
  using J = nlohmann::json;
  variant("no_schema", [](J& f, J&) { f.erase("schema"); });
  variant("banana_schema", [](J& f, J&) { f["schema"] = "skelgrasp.banana/1"; });
  variant("position_1e308", [](J&, J& g) { g["hand_pose"]["position"] = {1e308, 0, 0}; });
  variant("position_1001", [](J&, J& g) { g["hand_pose"]["position"] = {1001, 0, 0}; });
  variant("quaternion_2", [](J&, J& g) { g["hand_pose"]["quaternion_wxyz"] = {2, 0, 0, 0}; });
  variant("quaternion_1_01", [](J&, J& g) { g["hand_pose"]["quaternion_wxyz"] = {1.01, 0, 0, 0}; });
  variant("quaternion_1e308", [](J&, J& g) {
    g["hand_pose"]["quaternion_wxyz"] = {1e308, 1e308, 0, 0};
  });
  variant("joint_1e308", [](J&, J& g) { g["joints"].begin().value() = 1e308; });
  variant("joint_50", [](J&, J& g) { g["joints"].begin().value() = 50; });
  variant("joint_missing", [](J&, J& g) { g["joints"].erase(g["joints"].begin()); });
  variant("object_12", [](J& f, J&) { f["object"] = 12; });
  variant("retreat_negative", [](J&, J& g) { g["retreat_m"] = -5; });
  variant("retreat_1e308", [](J&, J& g) { g["retreat_m"] = 1e308; });
  // An id nested 100 000 arrays deep: written as text, nlohmann would recurse to dump it.
  std::string deep = valid.dump();
  const std::string id = "\"id\":0";
  deep.replace(deep.find(id), id.size(),
               "\"id\":" + std::string(100000, '[') + std::string(100000, ']'));
  writeText(dir + "/deep_id.json", deep);
}

// Every file the cases below name, in the test's folder.
void writeHostileFiles(const std::string& dir) {
  writeText(dir + "/collinear.ply", kCollinearPly);
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  writeCaptures(dir);
  writeHands(dir);
  writeGraspsFiles(dir);
  writeText(dir + "/devices.txt", "/dev/zero\n");
}

class HostileInputCli : public ::testing::TestWithParam<BadCliInput> {};

TEST_P(HostileInputCli, ExitsTwoWithOneLineAndWritesNothing) {
  const auto& c = GetParam();
  const std::string dir = test::tempDir("cli_hostile_" + c.name);
  writeHostileFiles(dir);
  const std::string args = withDir(c.args, dir);
  for (const std::string quiet : {"", "-q "}) {
    const CliRun r = runCli(quiet + args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string line = lastLine(r.err);
    EXPECT_EQ(line.rfind("skelgrasp: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(c.expected), std::string::npos) << r.err;
    if (!quiet.empty()) {
      EXPECT_EQ(countLines(r.err), 1) << r.err;
    }
    EXPECT_TRUE(r.out.empty()) << r.out;
    // Nothing named out* (the outputs and their hidden temporaries) is left behind.
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(name.rfind("out", 0), 0u) << "half-written output " << name;
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "temporary left " << name;
    }
  }
}

// The valid grasps file the hostile ones are made from is exported and scored: the checks refuse
// values, not files.
TEST(HostileInputCli, TheValidGraspsFileIsExportedAndScored) {
  const std::string dir = test::tempDir("cli_hostile_valid_grasps");
  saveMesh(dir + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  writeGraspsFiles(dir);
  const CliRun exported =
      runCli("export " + dir + "/valid.json --format moveit --out " + dir + "/g.yaml", dir);
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  const CliRun scored = runCli("score " + dir + "/valid.json " + dir +
                                   "/capsule.ply --robustness-samples 2 --out " + dir + "/s.json",
                               dir);
  EXPECT_EQ(scored.exit_code, 0) << scored.err;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, HostileInputCli,
    ::testing::Values(
        BadCliInput{"skeleton_collinear_mesh", "skeleton {dir}/collinear.ply --out {dir}/out",
                    "collinear.ply: degenerate mesh: no face has a positive area"},
        BadCliInput{"plan_collinear_mesh",
                    "plan {dir}/collinear.ply --hand sdh --out {dir}/out --render {dir}/out.png",
                    "collinear.ply: degenerate mesh: no face has a positive area"},
        // The surface planner sampled such a mesh until its time limit, logging every sample.
        BadCliInput{"plan_surface_collinear_mesh",
                    "plan {dir}/collinear.ply --hand sdh --planner surface --out {dir}/out",
                    "collinear.ply: degenerate mesh: no face has a positive area"},
        // Capture intrinsics, checked when the description is read.
        BadCliInput{"capture_cx_1e308_inline", "ingest {dir}/cx_inline.json --out {dir}/out.pcd",
                    "cx_inline.json: intrinsics cx = 1e+308 puts the principal point"},
        BadCliInput{"capture_cx_1e308_intr_file", "ingest {dir}/cx_file.json --out {dir}/out.pcd",
                    "cam.intr: intrinsics cx = 1e+308 puts the principal point"},
        BadCliInput{"capture_fx_1e308", "ingest {dir}/fx_huge.json --out {dir}/out.pcd",
                    "fx_huge.json: intrinsics fx = 1e+308 is not a focal length in [1, 1e+06]"},
        BadCliInput{"capture_width_fraction",
                    "ingest {dir}/width_fraction.json --out {dir}/out.pcd",
                    "width_fraction.json: intrinsics width = 640.5 is not a whole number"},
        // Depth images: the header's size against the cap and the intrinsics, before decoding.
        BadCliInput{"depth_size_disagrees", "ingest {dir}/mismatch.json --out {dir}/out.pcd",
                    "depth.npy: depth image is 2x2 but the intrinsics say 640x480"},
        BadCliInput{"depth_png_30000_square", "ingest {dir}/huge_png.json --out {dir}/out.pcd",
                    "huge.png: depth PNG declares 30000x30000 pixels; each side must be in [1, "
                    "20000]"},
        BadCliInput{"depth_png_rgb16", "ingest {dir}/rgb16.json --out {dir}/out.pcd",
                    "rgb16.png: expected a 16-bit single-channel depth PNG, the header says "
                    "16-bit colour type 2"},
        BadCliInput{"mask_png_truncated", "ingest {dir}/mask_truncated.json --out {dir}/out.pcd",
                    "mask_truncated.png: cannot decode image"},
        BadCliInput{"mask_png_16_bit", "ingest {dir}/mask16.json --out {dir}/out.pcd",
                    "mask16.png: expected an 8-bit mask PNG, the header says 16-bit"},
        BadCliInput{"depth_npy_30000_square", "ingest {dir}/huge_npy.json --out {dir}/out.pcd",
                    "huge.npy: depth array shape (30000, 30000) exceeds the largest image side"},
        // Hand files: bounded before they are read.
        BadCliInput{"hand_urdf_dev_zero",
                    "plan {dir}/capsule.ply --hand {dir}/zero.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "zero.urdf: is not a regular file"},
        BadCliInput{"grasp_description_dev_zero",
                    "plan {dir}/capsule.ply --hand {dir}/gripper.urdf --grasp-description "
                    "{dir}/zero.json --out {dir}/out",
                    "zero.json: is not a regular file"},
        BadCliInput{"hand_urdf_too_large",
                    "plan {dir}/capsule.ply --hand {dir}/big.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "big.urdf: URDF of 8388609 bytes exceeds the limit of 8388608 bytes"},
        BadCliInput{"hand_urdf_too_many_links",
                    "plan {dir}/capsule.ply --hand {dir}/links.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "links.urdf: URDF has more than 1000 link elements"},
        BadCliInput{"hand_link_mesh_too_large",
                    "plan {dir}/capsule.ply --hand {dir}/mesh.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "big.stl: link mesh of 16777217 bytes exceeds the limit of 16777216 bytes"},
        // Hand values: sizes, scales, offsets and mimics a hand cannot have.
        BadCliInput{"hand_box_size_zero",
                    "plan {dir}/capsule.ply --hand {dir}/box_size_zero.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "box_size_zero.urdf: link 'f' collision box has no volume"},
        BadCliInput{"hand_mesh_scale_1e30",
                    "plan {dir}/capsule.ply --hand {dir}/mesh_scale_1e30.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "mesh_scale_1e30.urdf: link 'f' collision mesh scale is 1e+30, outside"},
        BadCliInput{"hand_joint_origin_1e308",
                    "plan {dir}/capsule.ply --hand {dir}/joint_origin_1e308.urdf "
                    "--grasp-description {dir}/gripper.json --out {dir}/out",
                    "joint_origin_1e308.urdf: joint 'j' origin offset (m) is 1e+308, outside [0, "
                    "10]"},
        BadCliInput{"hand_self_mimic",
                    "plan {dir}/capsule.ply --hand {dir}/self_mimic.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "self_mimic.urdf: joint 'j' mimics itself"},
        BadCliInput{"hand_mimic_cycle",
                    "plan {dir}/capsule.ply --hand {dir}/mimic_cycle.urdf --grasp-description "
                    "{dir}/gripper.json --out {dir}/out",
                    "mimic_cycle.urdf: joint 'j' is in a cycle of mimic joints"},
        BadCliInput{"description_closing_step_tiny",
                    "plan {dir}/capsule.ply --hand {dir}/gripper.urdf --grasp-description "
                    "{dir}/step_1e-300.json --out {dir}/out",
                    "step_1e-300.json: 'step_m' is 1e-300, outside [1e-05, 0.05]"},
        BadCliInput{"description_torsional_friction_1e308",
                    "plan {dir}/capsule.ply --hand {dir}/gripper.urdf --grasp-description "
                    "{dir}/torsional_1e308.json --out {dir}/out",
                    "torsional_1e308.json: 'torsional_friction_m' is 1e+308, outside [0, 1000]"},
        BadCliInput{"description_gcp_zero_quaternion",
                    "plan {dir}/capsule.ply --hand {dir}/gripper.urdf --grasp-description "
                    "{dir}/gcp_zero_quaternion.json --out {dir}/out",
                    "gcp_zero_quaternion.json: preshape 'power' gcp: quaternion has length 0"},
        BadCliInput{"description_one_joint_two_fingers",
                    "plan {dir}/capsule.ply --hand {dir}/gripper.urdf --grasp-description "
                    "{dir}/one_joint_two_fingers.json --out {dir}/out",
                    "one_joint_two_fingers.json: finger 'right_jaw': joint 'finger_left' is "
                    "already driven by finger 'left_jaw'"},
        BadCliInput{"hand_urdf_kinematic_loop",
                    "plan {dir}/capsule.ply --hand {dir}/loop.urdf --grasp-description "
                    "{dir}/any_base.json --out {dir}/out",
                    "loop.urdf: hand 'parallel_gripper': kinematic loop at 'b'"},
        // Grasps files: export and score refuse what they would pass on.
        BadCliInput{"export_no_schema",
                    "export {dir}/no_schema.json --format moveit --out {dir}/out",
                    "no_schema.json: grasps file has no \"schema\""},
        BadCliInput{"export_unknown_schema",
                    "export {dir}/banana_schema.json --format moveit --out {dir}/out",
                    "banana_schema.json: grasps file has schema \"skelgrasp.banana/1\""},
        BadCliInput{"export_position_1e308",
                    "export {dir}/position_1e308.json --format moveit --out {dir}/out",
                    "position_1e308.json: grasp 0: \"hand_pose\" position is 1e+308 m from the "
                    "origin, more than the limit of 100 m"},
        BadCliInput{"export_position_1001",
                    "export {dir}/position_1001.json --format moveit --out {dir}/out",
                    "position is 1e+03 m from the origin"},
        BadCliInput{"export_quaternion_2",
                    "export {dir}/quaternion_2.json --format moveit --out {dir}/out",
                    "quaternion_2.json: grasp 0: \"hand_pose\" quaternion has length 2, not 1"},
        BadCliInput{"export_quaternion_1_01",
                    "export {dir}/quaternion_1_01.json --format moveit --out {dir}/out",
                    "quaternion has length 1.01, not 1"},
        BadCliInput{"export_quaternion_1e308",
                    "export {dir}/quaternion_1e308.json --format moveit --out {dir}/out",
                    "quaternion has length 1.41421e+308, not 1"},
        BadCliInput{"export_joint_1e308",
                    "export {dir}/joint_1e308.json --format moveit --out {dir}/out",
                    "is 1e+308, outside its limits"},
        BadCliInput{"export_joint_50", "export {dir}/joint_50.json --format moveit --out {dir}/out",
                    "is 50, outside its limits"},
        BadCliInput{"export_joint_missing",
                    "export {dir}/joint_missing.json --format moveit --out {dir}/out",
                    "joint_missing.json: grasp 0: \"joints\" lacks joint"},
        BadCliInput{"export_retreat_negative",
                    "export {dir}/retreat_negative.json --format moveit --out {dir}/out",
                    "grasp 0: \"retreat_m\" is -5, outside [0, 1] m"},
        BadCliInput{"export_retreat_1e308",
                    "export {dir}/retreat_1e308.json --format moveit --out {dir}/out",
                    "grasp 0: \"retreat_m\" is 1e+308, outside [0, 1] m"},
        BadCliInput{"export_object_is_a_number",
                    "export {dir}/object_12.json --format moveit --out {dir}/out",
                    "object_12.json: grasps file: \"object\" is not a string"},
        BadCliInput{"export_deep_id", "export {dir}/deep_id.json --format moveit --out {dir}/out",
                    "deep_id.json: JSON nesting deeper than 64 levels"},
        BadCliInput{"score_position_1001",
                    "score {dir}/position_1001.json {dir}/capsule.ply --out {dir}/out",
                    "position_1001.json: grasp 0: \"hand_pose\" position is 1e+03 m"},
        BadCliInput{"score_quaternion_2",
                    "score {dir}/quaternion_2.json {dir}/capsule.ply --out {dir}/out",
                    "quaternion_2.json: grasp 0: \"hand_pose\" quaternion has length 2"},
        BadCliInput{"score_no_schema",
                    "score {dir}/no_schema.json {dir}/capsule.ply --out {dir}/out",
                    "no_schema.json: grasps file has no \"schema\""},
        BadCliInput{"score_deep_id", "score {dir}/deep_id.json {dir}/capsule.ply --out {dir}/out",
                    "deep_id.json: JSON nesting deeper than 64 levels"},
        // An output that is an input would be overwritten by the command's own result.
        BadCliInput{"plan_out_is_the_mesh",
                    "plan {dir}/capsule.ply --hand sdh --out {dir}/capsule.ply",
                    "capsule.ply: is also an input of this command"},
        BadCliInput{"export_out_is_the_grasps_file",
                    "export {dir}/valid.json --format moveit --out {dir}/valid.json",
                    "valid.json: is also an input of this command"},
        BadCliInput{"score_out_is_the_grasps_file",
                    "score {dir}/valid.json {dir}/capsule.ply --out {dir}/./valid.json",
                    "valid.json: is also an input of this command"},
        // evaluate: a device as objects is refused before .lock and batch.json are made.
        BadCliInput{"evaluate_objects_dev_zero", "evaluate --objects /dev/zero --out {dir}/out",
                    "/dev/zero: is neither a directory nor a file"},
        BadCliInput{"evaluate_list_names_a_device",
                    "evaluate --objects {dir}/devices.txt --out {dir}/out",
                    "/dev/zero: is not a regular file (listed in"}),
    [](const auto& info) { return info.param.name; });

TEST(HostileInputCli, EvaluateRecordsADegenerateMeshAsAFailedRunAndFinishes) {
  const std::string dir = test::tempDir("cli_hostile_evaluate_degenerate");
  const std::string objects = dir + "/objects", out = dir + "/out";
  fs::create_directories(objects);
  writeText(objects + "/collinear.ply", kCollinearPly);
  saveMesh(objects + "/capsule.ply", geometry::shapes::makeNamedShape("capsule"));
  const std::string args = "evaluate --objects " + objects + " --out " + out +
                           " --hands sdh --planners skeleton --robustness-samples 4"
                           " --robustness-grasps 2 --timeout 0 --vertex-distance 0.01";
  // The first run and a resume with --retry-failed both finish; the failure names the file.
  for (const std::string extra : {"", " --retry-failed"}) {
    const CliRun r = runCli(args + extra, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream runs(out + "/runs.jsonl");
    const std::string text((std::istreambuf_iterator<char>(runs)), {});
    EXPECT_NE(text.find("collinear.ply: degenerate mesh"), std::string::npos) << text;
    EXPECT_NE(text.find("\"capsule.ply\""), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace skelgrasp
