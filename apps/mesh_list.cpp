#include "mesh_list.h"

#include <algorithm>
#include <filesystem>

#include "skelgrasp/common/error.h"
#include "skelgrasp/common/mesh_io.h"

namespace skelgrasp::cli {

std::vector<std::string> collectMeshFiles(const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  for (const auto& input : inputs) {
    if (fs::is_directory(input)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(input)) {
        const std::string ext = fileExtension(entry.path().string());
        if (entry.is_regular_file() &&
            (ext == "ply" || ext == "obj" || ext == "off" || ext == "stl")) {
          found.push_back(entry.path().string());
        }
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(input)) {
      // A device or a pipe (/dev/zero) has no end: hashing or reading it would never finish.
      if (!fs::is_regular_file(input)) throw IoError(input, "is neither a directory nor a file");
      files.push_back(input);
    } else {
      throw IoError(input, "no such file or directory");
    }
  }
  return files;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace skelgrasp::cli
