#pragma once

#include <cstdint>

#include "tocd/devices/instruments.hpp"

namespace tocd::devices {

/// Decodes the 49-register block at input registers 99..147 (map version + identity strings)
/// that every tocdlab Modbus register map shares; throws ProtocolError on another map version.
Identity decode_identity_block(const std::uint16_t* regs, std::uint16_t expected_version,
                               const std::string& instrument);

}  // namespace tocd::devices
