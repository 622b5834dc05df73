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

std::vector<std::uint16_t> string_to_registers(std::string_view text, std::size_t n_registers) {
  std::vector<std::uint16_t> regs(n_registers, 0);
  for (std::size_t i = 0; i < text.size() && i < 2 * n_registers; ++i) {
    const auto byte = static_cast<std::uint8_t>(text[i]);
    regs[i / 2] |= static_cast<std::uint16_t>(i % 2 == 0 ? byte << 8 : byte);
  }
  return regs;
}

std::string registers_to_string(const std::uint16_t* registers, std::size_t n_registers) {
  std::string out;
  for (std::size_t i = 0; i < n_registers; ++i) {
    for (const int shift : {8, 0}) {
      const char c = static_cast<char>((registers[i] >> shift) & 0xFF);
      if (c == '\0') return out;
      out.push_back(c);
    }
  }
  return out;
}

}  // namespace tocd::devices
