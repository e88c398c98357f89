#include "skelgrasp/common/logging.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>

namespace skelgrasp {
namespace {

// Captures what the library's logger writes while alive.
class CapturedLog {
 public:
  CapturedLog() : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(text_)) {
    log().sinks().push_back(sink_);
  }
  ~CapturedLog() {
    auto& sinks = log().sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
  }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;
  int lines() const {
    const std::string t = text_.str();
    return static_cast<int>(std::count(t.begin(), t.end(), '\n'));
  }
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::sinks::ostream_sink_mt> sink_;
};

TEST(ProgressReporter, WorkOfUnknownLengthIsReportedAtTheIntervalNotEveryStep) {
  const CapturedLog captured;
  ProgressReporter progress("sampling", 0, 60.0);
  for (std::size_t done = 1; done <= 10000; ++done) progress.step(done);
  EXPECT_EQ(captured.lines(), 1) << captured.text();  // the first step only, within the minute
  EXPECT_NE(captured.text().find("sampling: 1 done"), std::string::npos) << captured.text();
  EXPECT_EQ(captured.text().find("ETA"), std::string::npos) << captured.text();
}

TEST(ProgressReporter, KnownWorkReportsItsLastStep) {
  const CapturedLog captured;
  ProgressReporter progress("objects", 3, 60.0);
  for (std::size_t done = 1; done <= 3; ++done) progress.step(done);
  EXPECT_EQ(captured.lines(), 2) << captured.text();  // the first and the last
  EXPECT_NE(captured.text().find("objects: 3/3 (100%)"), std::string::npos) << captured.text();
}

}  // namespace
}  // namespace skelgrasp
