#pragma once

#include <array>
#include <cstdint>

namespace tocd::devices {

/// IEEE-754 single precision over two 16-bit Modbus registers, high word first ("ABCD",
/// big-endian word order): the order every tocdlab register map documents.
std::array<std::uint16_t, 2> float_to_registers(float value) noexcept;

/// Inverse of float_to_registers.
float registers_to_float(std::uint16_t high, std::uint16_t low) noexcept;

}  // namespace tocd::devices
