#include "modbus/modbus_driver.hpp"

#include <cmath>

#include <fmt/format.h>

#include "modbus/identity_block.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/devices/vacuum_registers.hpp"

namespace tocd::devices {

Identity read_identity_block(ModbusLink& link, std::uint16_t expected_version) {
  namespace m = tester_map;  // the identity layout is shared by every tocdlab register map
  std::array<std::uint16_t, 1 + m::identity_regs> regs{};
  link.read_input(m::in_map_version, static_cast<int>(regs.size()), regs.data(), "map version, identity");
  return decode_identity_block(regs.data(), expected_version, link.instrument());
}

PollBlock read_poll_block(ModbusLink& link, std::string_view what) {
  static_assert(std::tuple_size_v<PollBlock> == tester_map::in_poll_count &&
                std::tuple_size_v<PollBlock> == vacuum_map::in_poll_count);
  PollBlock r{};
  link.read_input(0, static_cast<int>(r.size()), r.data(), what);
  return r;
}

double finite_float(const ModbusLink& link, const PollBlock& block, int at, std::string_view name) {
  const double v = registers_to_float(block[at], block[at + 1]);
  if (!std::isfinite(v))
    throw ProtocolError(link.instrument(), register_operation("read", "input", at, 2, name),
                        fmt::format("the {} is not a finite number", name));
  return v;
}

}  // namespace tocd::devices
