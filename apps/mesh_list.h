#pragma once
#include <string>
#include <vector>

namespace skelgrasp::cli {

// Expands files and directories (non-recursive, sorted) into mesh files with a supported
// extension. Throws IoError for a path that does not exist.
std::vector<std::string> collectMeshFiles(const std::vector<std::string>& inputs);

double median(std::vector<double> values);

}  // namespace skelgrasp::cli
