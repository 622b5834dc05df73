#include "modbus/identity_block.hpp"

#include <fmt/format.h>

#include "tocd/core/printable.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"

namespace tocd::devices {

Identity decode_identity_block(const std::uint16_t* regs, std::uint16_t expected_version,
                               const std::string& instrument) {
  namespace m = tester_map;  // the identity layout is shared by every tocdlab register map
  if (regs[0] != expected_version)
    throw ProtocolError(
        instrument, "read of input register 99 (register map version)",
        fmt::format("register map version {} is not the supported version {}", regs[0], expected_version));
  const std::uint16_t* p = regs + 1;
  Identity id;
  // The registers hold whatever bytes the instrument chose: made printable here, before the
  // identity is stored in a run or shown, so no terminal control or invalid UTF-8 gets through.
  id.vendor = printable_text(registers_to_string(p, m::identity_vendor_regs));
  p += m::identity_vendor_regs;
  id.model = printable_text(registers_to_string(p, m::identity_model_regs));
  p += m::identity_model_regs;
  id.serial = printable_text(registers_to_string(p, m::identity_serial_regs));
  p += m::identity_serial_regs;
  id.firmware = printable_text(registers_to_string(p, m::identity_firmware_regs));
  return id;
}

}  // namespace tocd::devices
