#pragma once
// All library output goes through one spdlog logger that writes to stderr, so that stdout stays
// free for the CLI's summaries and JSON.
#include <spdlog/spdlog.h>

#include <chrono>
#include <mutex>
#include <string>

namespace skelgrasp {

// The library's logger ("skelgrasp", stderr). Created on first use.
spdlog::logger& log();

// Sets the level of the library's logger (e.g. spdlog::level::warn for --quiet).
void setLogLevel(spdlog::level::level_enum level);

// Monotonic stopwatch for stage diagnostics.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Reports progress of long batch work at most every `min_interval_s` seconds (thread-safe):
// "<what>: 12/40 (30%), ETA 14 s".
class ProgressReporter {
 public:
  ProgressReporter(std::string what, std::size_t total, double min_interval_s = 2.0);
  void step(std::size_t done);
  void finish();

 private:
  std::string what_;
  std::size_t total_;
  double min_interval_s_;
  double last_report_s_ = -1e9;
  Stopwatch watch_;
  std::mutex mutex_;  // step() may be called from worker threads
};

// Points stdout or stderr at /dev/null while alive, for third-party code that prints unasked
// (PCL's PoissonRecon on stdout, Debian's liboctomap on stderr). Process-wide: anything else
// written to that stream meanwhile, from any thread, is lost too, so keep the scope to the one
// call.
class SilencedStream {
 public:
  enum class Stream { kStdout, kStderr };
  explicit SilencedStream(Stream stream);
  ~SilencedStream();
  SilencedStream(const SilencedStream&) = delete;
  SilencedStream& operator=(const SilencedStream&) = delete;

 private:
  int fd_;
  int saved_ = -1;
};

}  // namespace skelgrasp
