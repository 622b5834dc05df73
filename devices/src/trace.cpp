#include "trace.hpp"

#include <algorithm>
#include <iterator>
#include <vector>

#include <fmt/format.h>

#include "tocd/core/log.hpp"

namespace tocd::devices {

spdlog::logger& trace_log() {
  static const std::shared_ptr<spdlog::logger> log = tocd::logger("devices");
  return *log;
}

std::string hex_bytes(std::span<const std::uint8_t> bytes, std::size_t limit) {
  std::string out;
  const std::size_t shown = std::min(bytes.size(), limit);
  out.reserve(shown * 3 + 24);
  for (std::size_t i = 0; i < shown; ++i)
    fmt::format_to(std::back_inserter(out), "{}{:02x}", i ? " " : "", bytes[i]);
  if (shown < bytes.size()) fmt::format_to(std::back_inserter(out), " ... ({} bytes)", bytes.size());
  return out;
}

std::string modbus_pdu_hex(int function, int address, int count, const std::uint16_t* registers,
                           int register_count) {
  std::vector<std::uint8_t> pdu{static_cast<std::uint8_t>(function), static_cast<std::uint8_t>(address >> 8),
                                static_cast<std::uint8_t>(address & 0xff)};
  if (count >= 0) {
    pdu.push_back(static_cast<std::uint8_t>(count >> 8));
    pdu.push_back(static_cast<std::uint8_t>(count & 0xff));
  }
  if (registers != nullptr && register_count > 0) {
    if (count >= 0) pdu.push_back(static_cast<std::uint8_t>(2 * register_count));  // byte count
    for (int i = 0; i < register_count; ++i) {
      pdu.push_back(static_cast<std::uint8_t>(registers[i] >> 8));
      pdu.push_back(static_cast<std::uint8_t>(registers[i] & 0xff));
    }
  }
  return hex_bytes(pdu, 512);
}

}  // namespace tocd::devices
