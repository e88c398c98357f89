#include "fuzz_targets.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/grasping/hand/hand_model.h"
#include "skelgrasp/grasping/io/contacts_io.h"
#include "skelgrasp/grasping/io/grasp_export.h"
#include "skelgrasp/grasping/io/grasps_file.h"
#include "skelgrasp/perception/cloud_io.h"
#include "skelgrasp/perception/image_io.h"
#include "skelgrasp/perception/scan.h"

namespace skelgrasp::fuzz {
namespace {

namespace fs = std::filesystem;

// One scratch folder per process: readers take paths, and the extension decides the format. It
// goes when the process ends normally; a fuzzer run starts thousands of processes, and each left
// its folder behind before.
class ScratchDir {
 public:
  ScratchDir()
      : path_(fs::temp_directory_path() / ("skelgrasp-fuzz-" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;  // a destructor must not throw; a leftover folder is harmless
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

const fs::path& scratchDir() {
  static const ScratchDir dir;
  return dir.path();
}

std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const fs::path path = scratchDir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

// Runs `read` and swallows the errors a reader is allowed to throw; anything else escapes.
template <class Read>
int expectOnlySkelgraspErrors(Read&& read) {
  try {
    read();
  } catch (const Error&) {
    // The documented way to refuse an input: one line naming the file and the problem.
  }
  return 0;
}

// A small depth image every capture description may refer to.
const std::string& depthImagePath() {
  static const std::string path = [] {
    // numpy .npy v1.0, little-endian float32, shape (2, 2).
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
    bytes += static_cast<char>(header.size() & 0xff);
    bytes += static_cast<char>(header.size() >> 8);
    bytes += header;
    const float depth[4] = {0.5f, 0.5f, 0.6f, 0.6f};
    bytes.append(reinterpret_cast<const char*>(depth), sizeof(depth));
    return writeInput("depth.npy", reinterpret_cast<const std::uint8_t*>(bytes.data()),
                      bytes.size());
  }();
  return path;
}

}  // namespace

int fuzzMeshReader(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {"ply", "obj", "off", "stl"};
  const std::string path =
      writeInput(std::string("mesh.") + kExtensions[data[0] % 4], data + 1, size - 1);
  return expectOnlySkelgraspErrors([&] { loadMesh(path); });
}

int fuzzCloudReader(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path =
      writeInput(std::string("cloud.") + (data[0] % 2 == 0 ? "pcd" : "ply"), data + 1, size - 1);
  return expectOnlySkelgraspErrors([&] { perception::loadPointCloud(path); });
}

int fuzzNpyReader(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeInput("image.npy", data, size);
  return expectOnlySkelgraspErrors([&] { perception::readDepthNpy(path); });
}

int fuzzCaptureDescription(const std::uint8_t* data, std::size_t size) {
  depthImagePath();  // the description may name "depth.npy", which then exists
  const std::string path = writeInput("capture.json", data, size);
  return expectOnlySkelgraspErrors([&] { perception::loadCapture(path); });
}

int fuzzGraspDescription(const std::uint8_t* data, std::size_t size) {
  // The parallel gripper's URDF names no mesh files, so the scratch folder serves as base.
  static const std::string urdf = grasping::builtinHandFiles("parallel_gripper").urdf;
  const std::string description(reinterpret_cast<const char*>(data), size);
  return expectOnlySkelgraspErrors([&] {
    grasping::loadHandFromText(urdf, description, scratchDir().string(), "fuzz.grasp.json");
  });
}

int fuzzContactsJson(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeInput("contacts.json", data, size);
  return expectOnlySkelgraspErrors([&] { grasping::readContactsFile(path); });
}

int fuzzGraspsFile(const std::uint8_t* data, std::size_t size) {
  static const grasping::HandModel hand = grasping::loadBuiltinHand("sdh");
  const std::string path = writeInput("grasps.json", data, size);
  return expectOnlySkelgraspErrors([&] {
    const nlohmann::json file = readJsonFile(path);
    grasping::readGraspPlacements(file, hand);
    grasping::exportGrasps(file, hand, grasping::ExportFormat::kMoveIt);
  });
}

const std::vector<NamedTarget>& allTargets() {
  static const std::vector<NamedTarget> targets = {
      {"mesh_reader", fuzzMeshReader},
      {"cloud_reader", fuzzCloudReader},
      {"npy_reader", fuzzNpyReader},
      {"capture_description", fuzzCaptureDescription},
      {"grasp_description", fuzzGraspDescription},
      {"contacts_json", fuzzContactsJson},
      {"grasps_file", fuzzGraspsFile},
  };
  return targets;
}

}  // namespace skelgrasp::fuzz
