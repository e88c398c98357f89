#pragma once
// Resource guards: before a stage allocates, it estimates the memory it will need from its input
// and parameters and refuses (ResourceLimitExceeded) when the estimate exceeds the process-wide
// memory limit, instead of being killed by the kernel minutes later. Estimates are documented next
// to each stage and in docs/limits.md.
#include <cstdint>
#include <string>

#include "skelgrasp/common/error.h"

namespace skelgrasp {

// An estimated need exceeds the memory limit. An InvalidArgument: the parameters ask for more
// than this machine (or the limit the user set) allows, and a smaller value would work.
class ResourceLimitExceeded : public InvalidArgument {
 public:
  // `what`: the stage and its input ("Poisson reconstruction at depth 14 of 30000 points");
  // `parameter`: the option to change ("--poisson-depth").
  ResourceLimitExceeded(const std::string& what, double needed_bytes, double limit_bytes,
                        const std::string& parameter);
  double neededBytes() const { return needed_bytes_; }
  double limitBytes() const { return limit_bytes_; }

 private:
  double needed_bytes_;
  double limit_bytes_;
};

// Share of the available memory the default limit allows: half leaves room for the estimates'
// error (they are calibrated to within about 2x) and for the rest of the machine.
inline constexpr double kDefaultMemoryFraction = 0.5;

// Memory this process may use at most: the smallest of the machine's RAM (MemTotal in
// /proc/meminfo), the cgroup v2 limit (/sys/fs/cgroup/memory.max) and RLIMIT_AS.
std::uint64_t availableMemoryBytes();

// kDefaultMemoryFraction x availableMemoryBytes().
std::uint64_t defaultMemoryLimitBytes();

// The process-wide limit the guards check against (defaultMemoryLimitBytes() unless set).
std::uint64_t memoryLimitBytes();
void setMemoryLimitBytes(std::uint64_t bytes);

// "4G", "512M", "1.5GiB", "300k", "1000000" (bytes; K/M/G/T are powers of 1024, an optional
// trailing "B" or "iB" is ignored), or a fraction in (0, 1] of availableMemoryBytes() ("0.25").
// Throws InvalidArgument for anything else, zero or a non-finite value.
std::uint64_t parseMemoryLimit(const std::string& text);

// "1.5 GiB", "12 GiB", "3.2e+07 GiB" or (below 1 GiB) "300 MiB".
std::string formatBytes(double bytes);

// Throws ResourceLimitExceeded when `estimated_bytes` (any finite or infinite value) exceeds
// memoryLimitBytes() (a NaN estimate counts as exceeding).
void checkMemoryEstimate(const std::string& what, double estimated_bytes,
                         const std::string& parameter);

}  // namespace skelgrasp
