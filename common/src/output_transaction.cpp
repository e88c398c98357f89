// OutputTransaction (atomic_file.h): several outputs staged as hidden temporaries and renamed
// together, with the list of a command's outputs in a directory it owns.
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <system_error>

#include "atomic_file_internal.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp {

namespace fs = std::filesystem;
using namespace internal;

OutputTransaction::~OutputTransaction() {
  std::error_code ec;
  for (const auto& staged : staged_) fs::remove(staged.temporary, ec);
  if (!committed_) removeCreatedDirectories(created_directories_);
}

std::string OutputTransaction::stage(const std::string& final_path) {
  const fs::path target = resolveTarget(final_path);
  if (isSpecialFile(target)) return final_path;
  requireNotDirectory(target, final_path);
  for (const auto& staged : staged_) {
    if (staged.target == target.string()) return staged.temporary;
  }
  for (auto& dir : createParentDirectories(target, final_path)) {
    created_on_signal_.emplace_back(dir, SignalCleanupEntry::Kind::kEmptyDirectory);
    created_directories_.push_back(std::move(dir));
  }
  // Only a name: a writer that decides to write nothing (an empty picture) leaves no file, and
  // commit() then skips it.
  std::string temporary = temporarySiblingPath(target.string());
  SignalCleanupEntry on_signal(temporary, SignalCleanupEntry::Kind::kFile);
  staged_.push_back({std::move(temporary), target.string(), std::move(on_signal)});
  return staged_.back().temporary;
}

namespace {

// The names an output list (kOutputListFile) in `dir` holds: plain visible file names only (no
// path, nothing starting with "."), so that a hostile list can reach neither outside the directory
// nor its lock or list.
std::set<std::string> readOutputList(const fs::path& dir) {
  const fs::path list = dir / kOutputListFile;
  std::error_code ec;
  const auto bytes = fs::file_size(list, ec);
  if (ec || bytes > kMaxOutputListBytes) return {};
  std::ifstream in(list);
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '.' || line.find('/') != std::string::npos ||
        line.find('\0') != std::string::npos)
      continue;
    names.insert(line);
  }
  return names;
}

void writeOutputList(const fs::path& dir, const std::set<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += name + "\n";
  writeFileAtomically((dir / kOutputListFile).string(), text);
}

}  // namespace

void OutputTransaction::replacePreviousOutputsIn(const std::string& dir) {
  owned_directory_ = dir;
}

void OutputTransaction::commit() {
  std::error_code ec;
  // The files of the owned directory this commit writes, by name.
  const fs::path owned = owned_directory_.empty() ? fs::path() : absoluteNormal(owned_directory_);
  std::set<std::string> written;
  for (const auto& staged : staged_) {
    const fs::path target = absoluteNormal(staged.target);
    if (!owned.empty() && target.parent_path() == owned && fs::exists(staged.temporary, ec))
      written.insert(target.filename().string());
  }
  // The directories written to: a command killed there earlier may have left hidden temporaries,
  // which this one, writing the same files anew, clears (removeStaleTemporaries: only those of
  // processes that no longer run).
  std::set<fs::path> directories;
  for (const auto& staged : staged_)
    directories.insert(absoluteNormal(staged.target).parent_path());
  std::set<std::string> previous;
  if (!owned.empty()) {
    previous = readOutputList(owned);
    // Listed before the renames: at any moment the list names every file a command owns here.
    std::set<std::string> both = previous;
    both.insert(written.begin(), written.end());
    if (both != previous) writeOutputList(owned, both);
  }
  while (!staged_.empty()) {
    const Staged& staged = staged_.front();
    if (fs::exists(staged.temporary, ec))
      replaceWith(staged.temporary, staged.target, staged.target);
    staged_.erase(staged_.begin());
  }
  committed_ = true;
  created_on_signal_.clear();
  for (const auto& directory : directories) removeStaleTemporaries(directory.string());
  if (owned.empty()) return;
  for (const auto& name : previous) {
    if (written.count(name)) continue;
    if (fs::is_regular_file(fs::symlink_status(owned / name, ec))) fs::remove(owned / name, ec);
  }
  writeOutputList(owned, written);
}

}  // namespace skelgrasp
