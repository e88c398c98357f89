#include "skelgrasp/common/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <mutex>

namespace skelgrasp {

spdlog::logger& log() {
  static std::shared_ptr<spdlog::logger> logger = [] {
    auto existing = spdlog::get("skelgrasp");
    if (existing) return existing;
    auto created = spdlog::stderr_color_mt("skelgrasp");
    created->set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
    return created;
  }();
  return *logger;
}

void setLogLevel(spdlog::level::level_enum level) {
  log().set_level(level);
}

ProgressReporter::ProgressReporter(std::string what, std::size_t total, double min_interval_s)
    : what_(std::move(what)), total_(total), min_interval_s_(min_interval_s) {}

void ProgressReporter::step(std::size_t done) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double now = watch_.seconds();
  // A total of 0 is work of unknown length (a planner running until its time limit): reported at
  // the same interval, without a share or an ETA. Counting it as finished reported every step
  // (the surface planner logged each of ten million hypotheses).
  const bool known_total = total_ > 0;
  const bool last_step = known_total && done >= total_;
  if (now - last_report_s_ < min_interval_s_ && !last_step) return;
  last_report_s_ = now;
  if (!known_total) {
    log().info("{}: {} done, elapsed {:.1f} s", what_, done, now);
    return;
  }
  const double fraction = static_cast<double>(done) / total_;
  const double eta = done > 0 && done < total_ ? now / done * (total_ - done) : 0.0;
  log().info("{}: {}/{} ({:.0f}%), elapsed {:.1f} s, ETA {:.0f} s", what_, done, total_,
             100.0 * fraction, now, eta);
}

void ProgressReporter::finish() {
  log().info("{}: {}/{} done in {:.1f} s", what_, total_, total_, watch_.seconds());
}

SilencedStream::SilencedStream(Stream stream)
    : fd_(stream == Stream::kStdout ? STDOUT_FILENO : STDERR_FILENO) {
  std::fflush(stream == Stream::kStdout ? stdout : stderr);
  saved_ = ::dup(fd_);
  const int null = ::open("/dev/null", O_WRONLY);
  if (saved_ >= 0 && null >= 0) ::dup2(null, fd_);
  if (null >= 0) ::close(null);
}

SilencedStream::~SilencedStream() {
  std::fflush(fd_ == STDOUT_FILENO ? stdout : stderr);
  if (saved_ >= 0) {
    ::dup2(saved_, fd_);
    ::close(saved_);
  }
}

}  // namespace skelgrasp
