#pragma once
// Helpers shared by the test suites.
#include <gtest/gtest.h>

#include <stdlib.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace skelgrasp::test {

// ../shared/data next to the checkout (CI has it); empty string when absent.
inline std::string sharedDataDir() {
  const std::string dir = SKELGRASP_SHARED_DATA_DIR;
  return std::filesystem::is_directory(dir) ? dir : std::string();
}

// Files with one of the extensions in a sub-directory of the shared data, sorted.
inline std::vector<std::string> sharedFiles(const std::string& subdir,
                                            const std::vector<std::string>& extensions) {
  std::vector<std::string> files;
  const std::string root = sharedDataDir();
  if (root.empty() || !std::filesystem::is_directory(root + "/" + subdir)) return files;
  for (const auto& e : std::filesystem::directory_iterator(root + "/" + subdir)) {
    for (const auto& ext : extensions) {
      if (e.path().extension() == ext) files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

namespace detail {

// Removes the directories tempDir made during a test when the test ends (kept when the
// environment variable SKELGRASP_KEEP_TEST_DIRS is set, to look at a failure).
class TempDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  static std::vector<std::string>& made() {
    static std::vector<std::string> dirs;
    return dirs;
  }
  void OnTestEnd(const ::testing::TestInfo&) override {
    if (std::getenv("SKELGRASP_KEEP_TEST_DIRS") == nullptr) {
      for (const auto& dir : made()) {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
      }
    }
    made().clear();
  }
};

// Registered once per test program, before main (gtest owns the listener).
inline const bool kTempDirCleanerRegistered = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new TempDirCleaner);
  return true;
}();

// Characters of a test name that are safe in a file name.
inline std::string fileNameSafe(std::string text) {
  for (char& c : text) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '_' || c == '-' || c == '.';
    if (!keep) c = '_';
  }
  return text;
}

}  // namespace detail

// A fresh, empty temporary directory of its own for the running test: its name holds the test's
// name, `name`, the process id and a unique suffix (mkdtemp), so parameterised tests and tests run
// in parallel by `ctest -j` never share one. Removed when the test ends.
inline std::string tempDir(const std::string& name) {
  std::string test = "no_test";
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    test = std::string(info->test_suite_name()) + "." + info->name();
  const auto pattern = std::filesystem::temp_directory_path() /
                       detail::fileNameSafe("skelgrasp_test_" + test + "_" + name + "_" +
                                            std::to_string(::getpid()) + "_XXXXXX");
  std::string buffer = pattern.string();
  if (::mkdtemp(buffer.data()) == nullptr) {
    ADD_FAILURE() << "cannot create a temporary directory " << buffer;
    return buffer;
  }
  detail::TempDirCleaner::made().push_back(buffer);
  return buffer;
}

}  // namespace skelgrasp::test

#define SKELGRASP_REQUIRE_SHARED_DATA()                                        \
  do {                                                                         \
    if (::skelgrasp::test::sharedDataDir().empty())                            \
      GTEST_SKIP() << "shared data not found at " SKELGRASP_SHARED_DATA_DIR    \
                      " (real-data test skipped; CI provides ../shared/data)"; \
  } while (0)
