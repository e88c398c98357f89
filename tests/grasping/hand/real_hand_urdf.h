#pragma once
// Test helper: a URDF of a real hand model (Simox facts resolved in
// ../shared/data/hands/*/hand.json, with the real collision meshes), named so that the built-in
// hand's grasp description applies.
#include <string>

namespace skelgrasp::test {

// `hand_dir` = ../shared/data/hands/<folder>, `builtin` = armar3 | sdh | shadow | parallel_gripper.
// Writes <out_dir>/<builtin>_real.urdf and returns its path.
std::string writeRealHandUrdf(const std::string& hand_dir, const std::string& builtin,
                              const std::string& out_dir);

}  // namespace skelgrasp::test
