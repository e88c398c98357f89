#include "skelgrasp/common/resources.h"

#include <gtest/gtest.h>

#include <limits>

namespace skelgrasp {
namespace {

constexpr std::uint64_t kMiB = 1024ull * 1024;
constexpr std::uint64_t kGiB = 1024 * kMiB;

TEST(Resources, AvailableMemoryIsPositiveAndTheDefaultIsHalfOfIt) {
  const std::uint64_t available = availableMemoryBytes();
  EXPECT_GT(available, 64 * kMiB);
  EXPECT_EQ(defaultMemoryLimitBytes(),
            static_cast<std::uint64_t>(kDefaultMemoryFraction * static_cast<double>(available)));
}

TEST(Resources, ParsesSizesWithSuffixesAndFractions) {
  EXPECT_EQ(parseMemoryLimit("4G"), 4 * kGiB);
  EXPECT_EQ(parseMemoryLimit("4g"), 4 * kGiB);
  EXPECT_EQ(parseMemoryLimit("512M"), 512 * kMiB);
  EXPECT_EQ(parseMemoryLimit("512MB"), 512 * kMiB);
  EXPECT_EQ(parseMemoryLimit("1.5GiB"), 3 * kGiB / 2);
  EXPECT_EQ(parseMemoryLimit("2048K"), 2 * kMiB);
  EXPECT_EQ(parseMemoryLimit("1T"), 1024 * kGiB);
  EXPECT_EQ(parseMemoryLimit("1000000000"), 1000000000ull);
  const double available = static_cast<double>(availableMemoryBytes());
  EXPECT_EQ(parseMemoryLimit("0.25"), static_cast<std::uint64_t>(0.25 * available));
  EXPECT_EQ(parseMemoryLimit("1.0"), static_cast<std::uint64_t>(available));
}

TEST(Resources, RejectsMalformedOrUselessLimits) {
  for (const char* text : {"", "lots", "G", "-4G", "0", "0.0", "4X", "4 G", "nan", "inf", "1e300",
                           "12", "1.5", "iB"}) {
    EXPECT_THROW(parseMemoryLimit(text), InvalidArgument) << text;
  }
}

TEST(Resources, CheckRefusesAboveTheLimitWithOneLine) {
  const std::uint64_t before = memoryLimitBytes();
  setMemoryLimitBytes(2 * kGiB);
  EXPECT_EQ(memoryLimitBytes(), 2 * kGiB);
  EXPECT_NO_THROW(checkMemoryEstimate("stage", 1.9 * kGiB, "--param"));
  try {
    checkMemoryEstimate("stage of 10 points", 3.0 * kGiB, "--param");
    ADD_FAILURE() << "no exception";
  } catch (const ResourceLimitExceeded& e) {
    const std::string what = e.what();
    EXPECT_EQ(what,
              "stage of 10 points: needs about 3.0 GiB (estimate), limit 2.0 GiB; raise with "
              "--memory-limit or change --param");
    EXPECT_DOUBLE_EQ(e.neededBytes(), 3.0 * kGiB);
    EXPECT_DOUBLE_EQ(e.limitBytes(), 2.0 * kGiB);
  }
  // Overflowed or undefined estimates refuse too, and are caught as caller mistakes.
  EXPECT_THROW(checkMemoryEstimate("x", std::numeric_limits<double>::infinity(), "p"),
               InvalidArgument);
  EXPECT_THROW(checkMemoryEstimate("x", std::numeric_limits<double>::quiet_NaN(), "p"),
               ResourceLimitExceeded);
  EXPECT_THROW(setMemoryLimitBytes(0), InvalidArgument);
  setMemoryLimitBytes(before);
}

TEST(Resources, FormatsSizesForHumans) {
  EXPECT_EQ(formatBytes(3.0 * kGiB), "3.0 GiB");
  EXPECT_EQ(formatBytes(23.4 * kGiB), "23 GiB");
  EXPECT_EQ(formatBytes(300.0 * kMiB), "300 MiB");
  EXPECT_EQ(formatBytes(10), "1 MiB");
  EXPECT_EQ(formatBytes(1e300), "9.3e+290 GiB");
  EXPECT_EQ(formatBytes(std::numeric_limits<double>::infinity()), "more than 1e+300 GiB");
}

}  // namespace
}  // namespace skelgrasp
