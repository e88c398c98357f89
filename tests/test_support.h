#pragma once
// Helpers shared by the test suites.
#include <gtest/gtest.h>

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

// A fresh temporary directory for one test.
inline std::string tempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("skelgrasp_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace skelgrasp::test

#define SKELGRASP_REQUIRE_SHARED_DATA()                                        \
  do {                                                                         \
    if (::skelgrasp::test::sharedDataDir().empty())                            \
      GTEST_SKIP() << "shared data not found at " SKELGRASP_SHARED_DATA_DIR    \
                      " (real-data test skipped; CI provides ../shared/data)"; \
  } while (0)
