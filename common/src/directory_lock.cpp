#include "skelgrasp/common/directory_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/common/logging.h"

namespace skelgrasp {
namespace {

std::string lockPath(const std::string& dir) {
  return dir + "/" + kDirectoryLockFile;
}

// The process id written in the lock file, -1 when there is none.
long readHolder(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
  if (n <= 0) return -1;
  char* end = nullptr;
  const long pid = std::strtol(text, &end, 10);
  return end != text && pid > 0 ? pid : -1;
}

std::string inUse(long pid) {
  return pid > 0 ? "is in use by process " + std::to_string(pid)
                 : std::string("is in use by another process");
}

}  // namespace

DirectoryLock::DirectoryLock(const std::string& dir) {
  fd_ = ::open(lockPath(dir).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw IoError(dir, std::string("cannot write here: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const long pid = readHolder(fd_);
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) throw IoError(dir, inUse(pid));
    throw IoError(dir, std::string("cannot lock: ") + std::strerror(error));
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The lock holds without the id; a second process then says "another process".
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

std::optional<long> lockHolder(const std::string& dir) {
  const int fd = ::open(lockPath(dir).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  std::optional<long> holder;
  if (::flock(fd, LOCK_SH | LOCK_NB) != 0) {
    holder = readHolder(fd);
  } else {
    ::flock(fd, LOCK_UN);
  }
  ::close(fd);
  return holder;
}

LockedOutputDirectory::LockedOutputDirectory(const std::string& dir) : dir_(dir) {
  created_directories_ = createOutputDirectory(dir);
  if (created()) {
    // Registered before the lock file exists: a signal between the two still removes both.
    on_signal_.emplace_back(lockPath(dir), SignalCleanupEntry::Kind::kFile);
    for (const auto& created : created_directories_)
      on_signal_.emplace_back(created, SignalCleanupEntry::Kind::kEmptyDirectory);
  }
  try {
    lock_ = std::make_unique<DirectoryLock>(dir);
  } catch (...) {
    removeIfLeftEmpty();
    throw;
  }
  if (const std::size_t removed = removeStaleTemporaries(dir))
    log().info("{}: removed {} temporary file(s) of a command that was killed", dir, removed);
}

LockedOutputDirectory::~LockedOutputDirectory() {
  removeIfLeftEmpty();  // the lock file goes while the lock is held
  lock_.reset();
}

void LockedOutputDirectory::removeIfLeftEmpty() {
  if (!created()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir_, ec)) {
    if (entry.path().filename() != kDirectoryLockFile) return;  // the command's outputs
  }
  if (ec) return;
  fs::remove(lockPath(dir_), ec);
  for (auto it = created_directories_.rbegin(); it != created_directories_.rend(); ++it)
    fs::remove(*it, ec);  // only if empty
}

}  // namespace skelgrasp
