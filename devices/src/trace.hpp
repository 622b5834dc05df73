#pragma once

// Instrument traffic at trace level (`tocdlab --log-level trace`): Modbus PDUs, SCPI lines and
// USBTMC transfers in hex or text, on the "devices" logger. Every call site tests
// trace_enabled() first, so with tracing off no line is formatted and no byte is converted.

#include <cstdint>
#include <span>
#include <string>

#include <spdlog/logger.h>

namespace tocd::devices {

/// The "devices" logger, looked up once.
spdlog::logger& trace_log();

inline bool trace_enabled() {
  return trace_log().should_log(spdlog::level::trace);
}

/// "01 02 ff" for bytes; at most `limit` bytes, then "... (N bytes)".
std::string hex_bytes(std::span<const std::uint8_t> bytes, std::size_t limit = 64);

/// A Modbus PDU in hex: function code, 16-bit address and count, then the registers.
std::string modbus_pdu_hex(int function, int address, int count, const std::uint16_t* registers = nullptr,
                           int register_count = 0);

}  // namespace tocd::devices
