#pragma once
// An exclusive advisory lock (flock) on DIR/.lock that keeps two processes from writing one output
// directory (an `evaluate` batch, a `run --out`). The kernel drops it when the process ends in any
// way (SIGKILL too), so a stale lock file never blocks a later run. The file itself stays (but with
// a directory LockedOutputDirectory made and removes again): removing it would race with a process
// that has opened it but not locked it yet.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skelgrasp/common/signal_cleanup.h"

namespace skelgrasp {

// The lock file's name inside the locked directory.
inline constexpr const char* kDirectoryLockFile = ".lock";

class DirectoryLock {
 public:
  // Takes the lock without waiting and writes this process's id into the lock file. Throws
  // IoError "DIR: is in use by process PID" when another holds it, or when DIR is not writable.
  explicit DirectoryLock(const std::string& dir);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// The id of the process holding DIR's lock; nullopt when nobody does (or DIR has no lock file).
// -1 when it is held but the holder did not write its id.
std::optional<long> lockHolder(const std::string& dir);

// The output directory of one command (`run --out DIR`) while it works: created when missing,
// locked (DirectoryLock: a second command into DIR at once exits with "DIR: is in use by process
// PID"), and cleared of the hidden temporaries that killed commands left (removeStaleTemporaries).
// A directory it created is removed again when the command leaves nothing in it but the lock
// file: on destruction (an error) and on SIGINT/SIGTERM/SIGHUP (signal_cleanup.h).
class LockedOutputDirectory {
 public:
  // Throws IoError naming DIR (not creatable, in use, not writable).
  explicit LockedOutputDirectory(const std::string& dir);
  ~LockedOutputDirectory();
  LockedOutputDirectory(const LockedOutputDirectory&) = delete;
  LockedOutputDirectory& operator=(const LockedOutputDirectory&) = delete;

  bool created() const { return !created_directories_.empty(); }

 private:
  // With a directory it created: removes the lock file and the directories it made when nothing
  // else is in them.
  void removeIfLeftEmpty();

  std::string dir_;
  std::vector<std::string> created_directories_;  // outermost first
  std::vector<SignalCleanupEntry> on_signal_;
  std::unique_ptr<DirectoryLock> lock_;
};

}  // namespace skelgrasp
