// Every input under fuzz/regressions/<target>/ (inputs that once crashed a reader, or hand-made
// edge cases) goes through its fuzz target: it must be refused with a skelgrasp::Error or read,
// never crash or throw anything else. `make sanitize` runs this under ASan/UBSan.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.h"

namespace skelgrasp::fuzz {
namespace {

namespace fs = std::filesystem;

struct RegressionInput {
  std::string target;
  fs::path file;
};

std::vector<RegressionInput> regressionInputs() {
  std::vector<RegressionInput> inputs;
  const fs::path root = fs::path(SKELGRASP_SOURCE_DIR) / "fuzz" / "regressions";
  for (const auto& target : allTargets()) {
    const fs::path dir = root / target.name;
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) inputs.push_back({target.name, f});
  }
  return inputs;
}

Target targetNamed(const std::string& name) {
  for (const auto& t : allTargets())
    if (name == t.name) return t.run;
  return nullptr;
}

class FuzzRegression : public ::testing::TestWithParam<RegressionInput> {};

TEST_P(FuzzRegression, IsReadOrRefusedWithSkelgraspError) {
  const auto& input = GetParam();
  std::ifstream in(input.file, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  const Target target = targetNamed(input.target);
  ASSERT_NE(target, nullptr);
  EXPECT_EQ(target(bytes.data(), bytes.size()), 0) << input.file;
}

TEST(FuzzRegression, EveryTargetHasRegressionInputs) {
  const auto inputs = regressionInputs();
  for (const auto& t : allTargets()) {
    const auto n = std::count_if(inputs.begin(), inputs.end(),
                                 [&](const RegressionInput& i) { return i.target == t.name; });
    EXPECT_GT(n, 0) << "fuzz/regressions/" << t.name << " is empty";
  }
}

std::string testName(const ::testing::TestParamInfo<RegressionInput>& info) {
  std::string name = info.param.target + "_" + info.param.file.filename().string();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Inputs, FuzzRegression, ::testing::ValuesIn(regressionInputs()), testName);

}  // namespace
}  // namespace skelgrasp::fuzz
