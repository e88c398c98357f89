#pragma once
// Fuzz targets of skelgrasp's file readers. Each takes the bytes of one input file, hands them to
// a reader the way a user's file reaches it (a real file with the right extension) and returns 0.
// A reader may reject the input only with skelgrasp::Error (IoError, InvalidArgument): any other
// exception escaping, a crash, a hang or a sanitizer report is a finding.
//
// The same functions are linked into the libFuzzer binaries (clang, `make fuzz`) and into the
// regression test of `make test`, which replays every file under fuzz/regressions/<target>/.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace skelgrasp::fuzz {

using Target = int (*)(const std::uint8_t* data, std::size_t size);

struct NamedTarget {
  const char* name;
  Target run;
};

// Mesh readers (PLY, OBJ, OFF, STL): the first byte picks the extension, the rest is the file.
int fuzzMeshReader(const std::uint8_t* data, std::size_t size);
// Point cloud readers (PCD, PLY): the first byte picks the extension.
int fuzzCloudReader(const std::uint8_t* data, std::size_t size);
// Depth image .npy reader.
int fuzzNpyReader(const std::uint8_t* data, std::size_t size);
// RGB-D capture description (JSON naming a depth image that exists).
int fuzzCaptureDescription(const std::uint8_t* data, std::size_t size);
// Grasp description of a hand (JSON), loaded with the built-in parallel gripper's URDF.
int fuzzGraspDescription(const std::uint8_t* data, std::size_t size);
// JSON documents read by the CLI (contacts of `quality`, grasps.json): the generic JSON reader
// and the contact list reader.
int fuzzContactsJson(const std::uint8_t* data, std::size_t size);
// Grasps files of `score` and `export` (grasps.json of plan or run), read with the built-in SDH
// hand: the placements `score` reads and the MoveIt export.
int fuzzGraspsFile(const std::uint8_t* data, std::size_t size);

// Every target, by the name used for its binary (fuzz_<name>) and its regression folder.
const std::vector<NamedTarget>& allTargets();

}  // namespace skelgrasp::fuzz
