#pragma once
// Internal: an exclusive advisory lock (flock) on DIR/.lock that keeps two processes from writing
// one batch directory. The kernel drops it when the process ends in any way (SIGKILL too), so a
// stale lock file never blocks a later run. The file itself stays: removing it would race with a
// process that has opened it but not locked it yet.
#include <optional>
#include <string>

namespace skelgrasp::evaluation::internal {

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

}  // namespace skelgrasp::evaluation::internal
