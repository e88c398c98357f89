#include "skelgrasp/common/resources.h"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace skelgrasp {
namespace {

constexpr double kBytesPerGiB = 1024.0 * 1024.0 * 1024.0;

// 0 = not set yet: the default is computed on first use (reading /proc costs a few microseconds,
// but a library linked into a test should not read it before anyone asks).
std::atomic<std::uint64_t> g_limit_bytes{0};

// The number in a file such as cgroup v2 memory.max ("max" or bytes); 0 when absent or "max".
std::uint64_t readLimitFile(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  try {
    return std::stoull(text);
  } catch (const std::exception&) {
    return 0;
  }
}

std::uint64_t memTotalBytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit) {
    if (key == "MemTotal:") return kib * 1024;
  }
  return 0;
}

}  // namespace

ResourceLimitExceeded::ResourceLimitExceeded(const std::string& what, double needed_bytes,
                                             double limit_bytes, const std::string& parameter)
    : InvalidArgument(what + ": needs about " + formatBytes(needed_bytes) + " (estimate), limit " +
                      formatBytes(limit_bytes) + "; raise with --memory-limit or change " +
                      parameter),
      needed_bytes_(needed_bytes),
      limit_bytes_(limit_bytes) {}

std::uint64_t availableMemoryBytes() {
  std::uint64_t bytes = std::numeric_limits<std::uint64_t>::max();
  const auto lower = [&bytes](std::uint64_t candidate) {
    if (candidate > 0) bytes = std::min(bytes, candidate);
  };
  lower(memTotalBytes());
  lower(readLimitFile("/sys/fs/cgroup/memory.max"));                    // cgroup v2
  lower(readLimitFile("/sys/fs/cgroup/memory/memory.limit_in_bytes"));  // cgroup v1
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) lower(as.rlim_cur);
  // Nothing readable (no /proc): assume a small machine rather than no limit at all.
  constexpr std::uint64_t kFallbackBytes = 4ull << 30;
  return bytes == std::numeric_limits<std::uint64_t>::max() ? kFallbackBytes : bytes;
}

std::uint64_t defaultMemoryLimitBytes() {
  return static_cast<std::uint64_t>(kDefaultMemoryFraction *
                                    static_cast<double>(availableMemoryBytes()));
}

std::uint64_t memoryLimitBytes() {
  std::uint64_t limit = g_limit_bytes.load();
  if (limit == 0) {
    limit = defaultMemoryLimitBytes();
    std::uint64_t unset = 0;
    g_limit_bytes.compare_exchange_strong(unset, limit);
  }
  return limit;
}

void setMemoryLimitBytes(std::uint64_t bytes) {
  if (bytes == 0) throw InvalidArgument("memory limit must be positive");
  g_limit_bytes.store(bytes);
}

std::uint64_t parseMemoryLimit(const std::string& text) {
  const auto bad = [&text]() {
    return InvalidArgument("--memory-limit: '" + text +
                           "' is not a size (e.g. 4G, 512M, 1000000) or a fraction in (0, 1]");
  };
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw bad();
  }
  if (!std::isfinite(value) || !(value > 0)) throw bad();
  std::string suffix = text.substr(used);
  for (auto& c : suffix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (suffix.size() >= 2 && suffix.compare(suffix.size() - 2, 2, "IB") == 0) {
    suffix.resize(suffix.size() - 2);
    if (suffix.empty()) throw bad();  // "iB" alone
  } else if (!suffix.empty() && suffix.back() == 'B') {
    suffix.pop_back();
  }
  double scale = 1;
  if (suffix == "K") {
    scale = 1024.0;
  } else if (suffix == "M") {
    scale = 1024.0 * 1024.0;
  } else if (suffix == "G") {
    scale = kBytesPerGiB;
  } else if (suffix == "T") {
    scale = kBytesPerGiB * 1024.0;
  } else if (!suffix.empty()) {
    throw bad();
  } else if (value <= 1 && text.find_first_of(".eE") != std::string::npos) {
    // A fraction ("0.25"); a plain "1" is one byte, which the range check below refuses.
    return static_cast<std::uint64_t>(value * static_cast<double>(availableMemoryBytes()));
  }
  const double bytes = value * scale;
  // Below a mebibyte nothing useful runs; above 2^63 the value cannot be represented.
  constexpr double kMinBytes = 1024.0 * 1024.0;
  if (bytes < kMinBytes || bytes >= 9.2e18) throw bad();
  return static_cast<std::uint64_t>(bytes);
}

std::string formatBytes(double bytes) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  const double gib = bytes / kBytesPerGiB;
  if (!std::isfinite(gib)) {
    out << "more than 1e+300 GiB";  // an estimate that overflowed a double
  } else if (gib >= 1e6) {
    out.setf(std::ios::scientific, std::ios::floatfield);
    out.precision(1);
    out << gib << " GiB";
  } else if (gib >= 1) {
    out.precision(gib < 10 ? 1 : 0);
    out << gib << " GiB";
  } else {
    out.precision(0);
    out << std::max(1.0, bytes / (1024.0 * 1024.0)) << " MiB";
  }
  return out.str();
}

void checkMemoryEstimate(const std::string& what, double estimated_bytes,
                         const std::string& parameter) {
  const auto limit = static_cast<double>(memoryLimitBytes());
  if (!(estimated_bytes <= limit)) {
    throw ResourceLimitExceeded(what, estimated_bytes, limit, parameter);
  }
}

}  // namespace skelgrasp
