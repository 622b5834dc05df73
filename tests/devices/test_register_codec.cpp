#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "tocd/devices/register_codec.hpp"

using tocd::devices::float_to_registers;
using tocd::devices::registers_to_float;

TEST(RegisterCodec, HighWordFirst) {
  // 1.0f = 0x3F800000, -2.5f = 0xC0200000
  EXPECT_EQ(float_to_registers(1.0f), (std::array<std::uint16_t, 2>{0x3F80, 0x0000}));
  EXPECT_EQ(float_to_registers(-2.5f), (std::array<std::uint16_t, 2>{0xC020, 0x0000}));
  EXPECT_EQ(registers_to_float(0x4049, 0x0FDB), 3.14159274101257324f);
}

TEST(RegisterCodec, RoundTripsEveryClass) {
  for (float v : {0.0f, -0.0f, 1e-40f, 123.456f, -9.81f, std::numeric_limits<float>::max()}) {
    const auto regs = float_to_registers(v);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(registers_to_float(regs[0], regs[1])),
              std::bit_cast<std::uint32_t>(v));
  }
  const auto nan = float_to_registers(std::numeric_limits<float>::quiet_NaN());
  EXPECT_TRUE(std::isnan(registers_to_float(nan[0], nan[1])));
}
