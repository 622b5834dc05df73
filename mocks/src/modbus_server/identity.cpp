#include "modbus_server/identity.hpp"

#include <algorithm>

#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"

namespace tocd::mocks {

void write_identity_block(std::uint16_t* in, std::uint16_t version, std::string_view vendor,
                          std::string_view model, std::string_view serial, std::string_view firmware) {
  namespace m = tocd::devices::tester_map;
  in[m::in_map_version] = version;
  std::uint16_t* p = in + m::in_identity;
  for (const auto& [text, n] :
       {std::pair{vendor, m::identity_vendor_regs}, std::pair{model, m::identity_model_regs},
        std::pair{serial, m::identity_serial_regs}, std::pair{firmware, m::identity_firmware_regs}}) {
    const auto regs = tocd::devices::string_to_registers(text, static_cast<std::size_t>(n));
    p = std::copy(regs.begin(), regs.end(), p);
  }
}

}  // namespace tocd::mocks
