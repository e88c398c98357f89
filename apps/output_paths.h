#pragma once
// Output paths are checked right after parsing, before any computing and before any file is
// written: a bad `--render /nonexistent/dir/x.png` fails at once with one error line instead of
// after minutes of work, and leaves the other outputs unwritten.
//
// The checks run at the start of each command's action rather than as CLI11 validators: errors
// then go through main()'s one-line "skelgrasp: error: <path>: <problem>" path (exit 2), and
// defaults (`--out run_output`) are checked too, which validators skip.
#include <filesystem>
#include <string>
#include <vector>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp::cli {

// An output file option; empty means "not requested". Throws IoError.
inline void checkOutputFileOption(const std::string& path) {
  if (!path.empty()) checkOutputFile(path);
}

// An output directory option (created when missing). Throws IoError.
inline void checkOutputDirectoryOption(const std::string& path) {
  if (!path.empty()) checkOutputDirectory(path);
}

// An output must not be one of the command's inputs: `plan m.ply --out m.ply` overwrote the
// mesh with its grasps, `export g.json --out g.json` the grasps with their export. Compared as
// the same file when both exist (links included), else as the same normalised path. Throws
// IoError naming the output.
inline void checkOutputIsNotInput(const std::string& out, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  if (out.empty()) return;
  for (const auto& input : inputs) {
    if (input.empty()) continue;
    std::error_code ec;
    const bool same = fs::exists(out, ec) && fs::exists(input, ec)
                          ? fs::equivalent(out, input, ec)
                          : fs::weakly_canonical(out, ec) == fs::weakly_canonical(input, ec);
    if (same) throw IoError(out, "is also an input of this command; give another output path");
  }
}

}  // namespace skelgrasp::cli
