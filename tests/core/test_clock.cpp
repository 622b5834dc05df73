#include <gtest/gtest.h>

#include "tocd/core/clock.hpp"

TEST(Clock, MonotonicNeverGoesBack) {
  std::int64_t previous = tocd::monotonic_ns();
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t now = tocd::monotonic_ns();
    ASSERT_GE(now, previous);
    previous = now;
  }
}

TEST(Clock, FormatsUtcWithMilliseconds) {
  EXPECT_EQ(tocd::format_utc(0), "1970-01-01T00:00:00.000Z");
  // 2026-11-24T02:33:55.123Z
  EXPECT_EQ(tocd::format_utc(1795487635'123'000'000LL), "2026-11-24T02:33:55.123Z");
  EXPECT_EQ(tocd::format_utc(-1'000'000), "1969-12-31T23:59:59.999Z");
}
