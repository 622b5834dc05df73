#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tocd::devices {

/// IEEE-754 single precision over two 16-bit Modbus registers, high word first ("ABCD",
/// big-endian word order): the order every tocdlab register map documents.
std::array<std::uint16_t, 2> float_to_registers(float value) noexcept;

/// Inverse of float_to_registers.
float registers_to_float(std::uint16_t high, std::uint16_t low) noexcept;

/// ASCII text over `n_registers` registers, two characters per register (first character in
/// the high byte), padded with NUL; longer text is cut.
std::vector<std::uint16_t> string_to_registers(std::string_view text, std::size_t n_registers);

/// Inverse of string_to_registers (stops at the first NUL).
std::string registers_to_string(const std::uint16_t* registers, std::size_t n_registers);

}  // namespace tocd::devices
