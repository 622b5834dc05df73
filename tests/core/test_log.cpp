#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"

TEST(Log, SameModuleSameLogger) {
  auto a = tocd::logger("unit-test");
  auto b = tocd::logger("unit-test");
  EXPECT_EQ(a.get(), b.get());
  EXPECT_EQ(a->name(), "unit-test");
}

TEST(Log, UnknownLevelIsAConfigError) {
  EXPECT_THROW(tocd::set_log_level("loud"), tocd::ConfigError);
  EXPECT_NO_THROW(tocd::set_log_level("off"));
  EXPECT_NO_THROW(tocd::set_log_level("warn"));
}
