#include "skelgrasp/common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <system_error>

#include "atomic_file_internal.h"
#include "skelgrasp/common/error.h"

namespace skelgrasp {
using namespace internal;
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kStreamBufferBytes = 1 << 16;
constexpr int kTemporaryNameAttempts = 100;  // unique names per process make 1 the usual count
constexpr mode_t kNewFileMode = 0666;        // narrowed by the umask, like std::ofstream

std::string errnoText(int error) {
  return std::error_code(error, std::generic_category()).message();
}

// A std::streambuf writing to a file descriptor that remembers the first errno.
class FdStreamBuf : public std::streambuf {
 public:
  explicit FdStreamBuf(int fd) : fd_(fd), buffer_(kStreamBufferBytes) { resetBuffer(); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }

  int sync() override { return drain() ? 0 : -1; }

  std::streamsize xsputn(const char* data, std::streamsize count) override {
    if (count <= epptr() - pptr()) {
      std::memcpy(pptr(), data, static_cast<std::size_t>(count));
      pbump(static_cast<int>(count));
      return count;
    }
    // Large blocks (mesh and image payloads) go straight to the file, past the buffer.
    if (!drain() || !writeAll(data, count)) return 0;
    return count;
  }

 private:
  void resetBuffer() { setp(buffer_.data(), buffer_.data() + buffer_.size()); }

  bool drain() {
    const std::streamsize pending = pptr() - pbase();
    if (pending > 0 && !writeAll(pbase(), pending)) return false;
    resetBuffer();
    return true;
  }

  bool writeAll(const char* data, std::streamsize count) {
    if (error_ != 0) return false;
    while (count > 0) {
      const ssize_t written = ::write(fd_, data, static_cast<std::size_t>(count));
      if (written < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      data += written;
      count -= written;
    }
    return true;
  }

  int fd_;
  std::vector<char> buffer_;
  int error_ = 0;
};

// fsync that tolerates files which cannot be synchronised (devices, pipes).
int syncDescriptor(int fd) {
  if (::fsync(fd) == 0 || errno == EINVAL || errno == EROFS) return 0;
  return errno;
}

// A file descriptor with an ostream over it; close() reports errors under `report_path`.
class FdWriter {
 public:
  FdWriter(int fd, std::string report_path)
      : fd_(fd), report_path_(std::move(report_path)), buffer_(fd), stream_(&buffer_) {}
  ~FdWriter() {
    if (fd_ >= 0) ::close(fd_);
  }
  std::ostream& stream() { return stream_; }

  void close() {
    stream_.flush();
    if (buffer_.error() != 0) fail("cannot write: " + errnoText(buffer_.error()));
    if (!stream_) fail("cannot write");
    if (const int error = syncDescriptor(fd_)) fail("cannot write: " + errnoText(error));
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail("cannot write: " + errnoText(errno));
  }

 private:
  [[noreturn]] void fail(const std::string& problem) { throw IoError(report_path_, problem); }

  int fd_;
  std::string report_path_;
  FdStreamBuf buffer_;
  std::ostream stream_;
};

}  // namespace

namespace internal {

fs::path absoluteNormal(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) p = path;
  return p.lexically_normal();
}

std::vector<fs::path> missingDirectories(const fs::path& file, const std::string& report_path,
                                         fs::path* existing) {
  std::vector<fs::path> missing;
  fs::path dir = absoluteNormal(file.string()).parent_path();
  std::error_code ec;
  while (!fs::exists(dir, ec) && dir.has_relative_path()) {
    missing.push_back(dir);
    dir = dir.parent_path();
  }
  if (!fs::is_directory(dir, ec)) throw IoError(report_path, dir.string() + " is not a directory");
  if (!missing.empty() && !dir.has_relative_path()) {
    throw IoError(report_path, "no such directory " + missing.front().string());
  }
  if (existing) *existing = dir;
  return missing;
}

void removeCreatedDirectories(const std::vector<std::string>& created) {
  std::error_code ec;
  for (auto it = created.rbegin(); it != created.rend(); ++it) fs::remove(*it, ec);  // if empty
}

std::vector<std::string> createParentDirectories(const fs::path& file,
                                                 const std::string& report_path) {
  const auto missing = missingDirectories(file, report_path, nullptr);
  std::vector<std::string> created;
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    std::error_code ec;
    if (fs::create_directory(*it, ec)) {
      created.push_back(it->string());
    } else if (ec) {
      removeCreatedDirectories(created);
      throw IoError(report_path, "cannot create directory " + it->string() + ": " + ec.message());
    }
  }
  return created;
}

}  // namespace internal

namespace {

// Opens a new temporary sibling of `target` exclusively: its descriptor and name, or -errno.
int openNewTemporary(const fs::path& target, std::string* name) {
  int error = 0;
  for (int attempt = 0; attempt < kTemporaryNameAttempts; ++attempt) {
    *name = temporarySiblingPath(target.string());
    const int fd = ::open(name->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, kNewFileMode);
    if (fd >= 0) return fd;
    error = errno;
    if (error != EEXIST) break;
  }
  return -error;
}

std::pair<std::string, int> createTemporaryFor(const fs::path& target,
                                               const std::string& report_path) {
  std::string name;
  const int fd = openNewTemporary(target, &name);
  if (fd < 0) {
    throw IoError(report_path, "cannot create a temporary file next to it: " + errnoText(-fd));
  }
  return {std::move(name), fd};
}

// Removes the temporary (and the directories made for it) unless released; a signal ending the
// process meanwhile removes them too (signal_cleanup.h).
class TemporaryGuard {
 public:
  TemporaryGuard(std::string path, std::vector<std::string> created_directories)
      : path_(std::move(path)), created_directories_(std::move(created_directories)) {
    on_signal_.emplace_back(path_, SignalCleanupEntry::Kind::kFile);
    for (const auto& dir : created_directories_)
      on_signal_.emplace_back(dir, SignalCleanupEntry::Kind::kEmptyDirectory);
  }
  ~TemporaryGuard() {
    if (!armed_) return;
    std::error_code ec;
    fs::remove(path_, ec);
    removeCreatedDirectories(created_directories_);
  }
  TemporaryGuard(const TemporaryGuard&) = delete;
  TemporaryGuard& operator=(const TemporaryGuard&) = delete;
  void release() { armed_ = false; }

 private:
  std::string path_;
  std::vector<std::string> created_directories_;
  std::vector<SignalCleanupEntry> on_signal_;
  bool armed_ = true;
};

}  // namespace

namespace internal {

fs::path resolveTarget(const std::string& path) {
  std::error_code ec;
  if (fs::is_symlink(path, ec) && fs::exists(path, ec)) {
    const fs::path target = fs::canonical(path, ec);
    if (!ec) return target;
  }
  return fs::path(path);
}

bool isSpecialFile(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  return !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
}

void requireNotDirectory(const fs::path& path, const std::string& report_path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(report_path, "is a directory");
}

void replaceWith(const std::string& temporary, const fs::path& target,
                 const std::string& report_path) {
  if (::rename(temporary.c_str(), target.c_str()) != 0) {
    throw IoError(report_path, "cannot replace it with the written file: " + errnoText(errno));
  }
  // The directory is not fsynced: after a crash the rename may be lost, which shows the old file
  // (still whole); only the data had to be on disk before it, and that fsync is done.
}

}  // namespace internal

namespace {

// An error naming the temporary or the path asked for (a staged name) is reported under
// `report_path`, the file it becomes.
[[noreturn]] void rethrowNamingTarget(const IoError& error, const std::string& temporary,
                                      const std::string& path, const std::string& report_path) {
  if (error.path() == temporary || error.path() == path)
    throw IoError(report_path, error.problem());
  throw error;
}

}  // namespace

std::string temporarySiblingPath(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  const fs::path p(path);
  const std::string name = "." + p.stem().string() + ".tmp." + std::to_string(::getpid()) + "." +
                           std::to_string(counter++) + p.extension().string();
  return (p.parent_path() / name).string();
}

std::string finalPathOfTemporary(const std::string& path) {
  const fs::path p(path);
  std::string name = p.filename().string();
  const std::string marker = ".tmp." + std::to_string(::getpid()) + ".";
  bool changed = false;
  // ".STEM.tmp.PID.N.EXT" -> "STEM.EXT", as often as it applies (a writer's temporary of a staged
  // name).
  while (name.size() > 1 && name[0] == '.') {
    const std::size_t at = name.rfind(marker);
    if (at == std::string::npos || at < 1) break;
    const std::size_t digits = at + marker.size();
    std::size_t end = digits;
    while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
    if (end == digits || (end < name.size() && name[end] != '.')) break;
    name = name.substr(1, at - 1) + name.substr(end);
    changed = true;
  }
  return changed ? (p.parent_path() / name).string() : path;
}

std::size_t removeStaleTemporaries(const std::string& dir) {
  static const std::regex temporary(R"(\..*\.tmp\.([0-9]+)\.[0-9]+(\..*)?)");
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    std::smatch match;
    if (!std::regex_match(name, match, temporary) || !entry.is_regular_file(ec)) continue;
    const long pid = std::strtol(match[1].str().c_str(), nullptr, 10);
    // Alive (or another user's, EPERM): its temporary may still become a file.
    if (pid <= 0 || pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH)
      continue;
    if (fs::remove(entry.path(), ec)) ++removed;
  }
  return removed;
}

std::vector<std::string> createOutputDirectory(const std::string& dir) {
  if (dir.empty()) throw InvalidArgument("an output directory is empty");
  std::error_code ec;
  const fs::path normal = absoluteNormal(dir);
  if (fs::exists(normal, ec)) {
    if (!fs::is_directory(normal, ec)) throw IoError(dir, "exists and is not a directory");
    return {};
  }
  return createParentDirectories(normal / "probe", dir);
}

void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream& out)>& write) {
  // A staged name of an OutputTransaction is reported as the file it becomes.
  const std::string report = finalPathOfTemporary(path);
  const fs::path target = resolveTarget(path);
  if (isSpecialFile(target)) {
    const int fd = ::open(target.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw IoError(report, "cannot open for writing: " + errnoText(errno));
    FdWriter direct(fd, report);
    write(direct.stream());
    direct.close();
    return;
  }
  requireNotDirectory(target, report);
  auto created = createParentDirectories(target, report);
  auto [temporary, fd] = createTemporaryFor(target, report);
  TemporaryGuard guard(temporary, std::move(created));
  FdWriter writer(fd, report);
  try {
    write(writer.stream());
  } catch (const IoError& e) {
    rethrowNamingTarget(e, temporary, path, report);
  }
  writer.close();
  replaceWith(temporary, target, report);
  guard.release();
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&text](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

void writeFileViaTemporary(const std::string& path,
                           const std::function<void(const std::string& temporary_path)>& write) {
  const std::string report = finalPathOfTemporary(path);
  const fs::path target = resolveTarget(path);
  if (isSpecialFile(target)) {
    write(target.string());
    return;
  }
  requireNotDirectory(target, report);
  auto created = createParentDirectories(target, report);
  auto [temporary, fd] = createTemporaryFor(target, report);
  ::close(fd);
  TemporaryGuard guard(temporary, std::move(created));
  try {
    write(temporary);
  } catch (const IoError& e) {
    rethrowNamingTarget(e, temporary, path, report);
  }
  // The library wrote by name; sync what it left there before it can replace the old file.
  const int written = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  if (written < 0) throw IoError(report, "the writer left no file: " + errnoText(errno));
  const int error = syncDescriptor(written);
  ::close(written);
  if (error != 0) throw IoError(report, "cannot write: " + errnoText(error));
  replaceWith(temporary, target, report);
  guard.release();
}

struct CheckedOutputFile::Impl {
  Impl(int fd, const std::string& path) : writer(fd, path) {}
  FdWriter writer;
};

CheckedOutputFile::CheckedOutputFile(const std::string& path, Mode mode) {
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (mode == Mode::kCreateNew ? O_EXCL : O_TRUNC);
  const int fd = ::open(path.c_str(), flags, kNewFileMode);
  if (fd < 0) throw IoError(path, "cannot open for writing: " + errnoText(errno));
  impl_ = std::make_unique<Impl>(fd, path);
}

CheckedOutputFile::~CheckedOutputFile() = default;

std::ostream& CheckedOutputFile::stream() {
  return impl_->writer.stream();
}

void CheckedOutputFile::close() {
  impl_->writer.close();
}

namespace {

// Creates and removes a probe file in `dir`: the only reliable test that files can be made there
// (permissions, read-only mounts, ACLs, a full inode table).
void probeDirectory(const fs::path& dir, const std::string& report_path) {
  std::string name;
  const int fd = openNewTemporary(dir / "skelgrasp-probe", &name);
  if (fd < 0) {
    throw IoError(report_path, "cannot create files in " + dir.string() + ": " + errnoText(-fd));
  }
  ::close(fd);
  ::unlink(name.c_str());
}

}  // namespace

void checkOutputFile(const std::string& path) {
  if (path.empty()) throw InvalidArgument("an output path is empty");
  const fs::path target = resolveTarget(path);
  if (isSpecialFile(target)) return;
  requireNotDirectory(target, path);
  fs::path existing;
  missingDirectories(target, path, &existing);
  probeDirectory(existing, path);
}

void checkOutputDirectory(const std::string& path) {
  if (path.empty()) throw InvalidArgument("an output directory is empty");
  std::error_code ec;
  const fs::path dir = absoluteNormal(path);
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw IoError(path, "exists and is not a directory");
    probeDirectory(dir, path);
    return;
  }
  fs::path existing;
  missingDirectories(dir / "probe", path, &existing);
  probeDirectory(existing, path);
}

}  // namespace skelgrasp
