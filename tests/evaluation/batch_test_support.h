#pragma once
// Shared by the batch tests (batch_test.cpp, batch_resume_test.cpp): readers of the files a batch
// writes and the fixture that makes three generated objects. A named namespace, not an anonymous
// one: gtest needs one fixture type for the test suite across both files.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/json.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/evaluation/batch.h"
#include "skelgrasp/geometry/shapes.h"
#include "test_support.h"

namespace skelgrasp::evaluation::batch_test {

inline std::vector<nlohmann::json> lines(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  }
  return out;
}

inline std::string textOf(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Everything except wall-clock times, which differ between runs by nature.
inline nlohmann::json withoutTimes(nlohmann::json j) {
  for (const char* key :
       {"planning_s", "regularise_s", "skeleton_s", "robustness_s", "ms_per_valid_grasp", "time_ms",
        "timed_out", "ranking_s", "ranked_refinement_s"}) {
    j.erase(key);
  }
  return j;
}

class BatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Per test: ctest runs the tests of this fixture in parallel processes.
    dir_ = test::tempDir(std::string("batch_objects_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    for (const char* shape : {"capsule", "bottle", "hammer"}) {
      objects_.push_back(dir_ + "/" + shape + ".ply");
      saveMesh(objects_.back(), geometry::shapes::makeNamedShape(shape));
    }
  }
  BatchParams params(const std::string& out) const {
    BatchParams p;
    p.objects = objects_;
    p.hands = {"sdh"};
    p.out_dir = out;
    p.timeout_s = 0;  // results must not depend on machine speed here
    p.vertex_distance_m = 0.01;
    p.surface_hypotheses = 40;
    p.robustness_grasps = 2;
    p.robustness.samples = 8;
    return p;
  }
  // The skeleton planner with a small robust ranking: the best `top_k` of `screen_k` screened
  // with 4 samples, scored with 6.
  BatchParams rankedParams(const std::string& out, std::size_t top_k, std::size_t screen_k) const {
    BatchParams p = params(out);
    p.planners = {ranking::Planner::kSkeleton};
    p.ranking.enabled = true;
    p.ranking.top_k = top_k;
    p.ranking.screen_k = screen_k;
    p.ranking.screen_samples = 4;
    p.ranking.robustness.samples = 6;
    return p;
  }
  std::string dir_;
  std::vector<std::string> objects_;
};

// Replaces the text `from` by `to` in line `line` (1-based) of `path`.
inline void editLine(const std::string& path, std::size_t line, const std::string& from,
                     const std::string& to) {
  std::vector<std::string> text;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) text.push_back(l);
  }
  ASSERT_GE(text.size(), line) << path;
  const auto at = text[line - 1].find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in line " << line << " of " << path;
  text[line - 1].replace(at, from.size(), to);
  std::ofstream out(path, std::ios::trunc);
  for (const auto& l : text) out << l << "\n";
}

// The IoError message of `action`, or a failure when it does not throw one.
template <typename Action>
std::string ioErrorOf(Action action) {
  try {
    action();
  } catch (const IoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no IoError";
  return "";
}

}  // namespace skelgrasp::evaluation::batch_test
