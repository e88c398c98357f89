#pragma once
// Output paths are checked right after parsing, before any computing and before any file is
// written: a bad `--render /nonexistent/dir/x.png` fails at once with one error line instead of
// after minutes of work, and leaves the other outputs unwritten.
//
// The checks run at the start of each command's action rather than as CLI11 validators: errors
// then go through main()'s one-line "skelgrasp: error: <path>: <problem>" path (exit 2), and
// defaults (`--out run_output`) are checked too, which validators skip.
#include <string>

#include "skelgrasp/common/atomic_file.h"

namespace skelgrasp::cli {

// An output file option; empty means "not requested". Throws IoError.
inline void checkOutputFileOption(const std::string& path) {
  if (!path.empty()) checkOutputFile(path);
}

// An output directory option (created when missing). Throws IoError.
inline void checkOutputDirectoryOption(const std::string& path) {
  if (!path.empty()) checkOutputDirectory(path);
}

}  // namespace skelgrasp::cli
