#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/mocks/sim_clock.hpp"

TEST(SimClock, RunsFasterByItsFactor) {
  tocd::mocks::SimClock fast(100.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  // 20 ms real at 100x is at least 2 s simulated (sleep never returns early).
  EXPECT_GE(fast.now_ns(), 2'000'000'000LL);
}

TEST(SimClock, RejectsNonPositiveFactor) {
  EXPECT_THROW(tocd::mocks::SimClock(0.0), tocd::ConfigError);
  EXPECT_THROW(tocd::mocks::SimClock(-1.0), tocd::ConfigError);
}
