#include "tocd/devices/register_codec.hpp"

#include <bit>

namespace tocd::devices {

std::array<std::uint16_t, 2> float_to_registers(float value) noexcept {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  return {static_cast<std::uint16_t>(bits >> 16), static_cast<std::uint16_t>(bits & 0xFFFFu)};
}

float registers_to_float(std::uint16_t high, std::uint16_t low) noexcept {
  return std::bit_cast<float>((static_cast<std::uint32_t>(high) << 16) | low);
}

}  // namespace tocd::devices
