#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "modbus/modbus_link.hpp"
#include "tocd/devices/capabilities.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::devices {

/// Input registers 0..5 of every tocdlab register map: two floats, a status word and a code,
/// read in one transaction per poll.
using PollBlock = std::array<std::uint16_t, 6>;

/// Reads the identity block at input registers 99..147 (map version + identity strings) and
/// decodes it (decode_identity_block).
Identity read_identity_block(ModbusLink& link, std::uint16_t expected_version);

/// Reads the polling block; `what` names its registers in error messages.
PollBlock read_poll_block(ModbusLink& link, std::string_view what);

/// The float at registers `at` and `at + 1` of a polling block; ProtocolError naming `name`
/// unless it is finite.
double finite_float(const ModbusLink& link, const PollBlock& block, int at, std::string_view name);

/// What a driver for a tocdlab register map does whatever the instrument: one ModbusLink,
/// opened on construction, the map's capability table and its identity block. `Interface` is
/// the driver interface it implements (MechanicalTester, VacuumController).
template <class Interface>
class ModbusDriver : public Interface {
 public:
  const InstrumentCapabilities& describe() const override { return capabilities_; }
  Identity identity() override { return read_identity_block(link_, map_version_); }

 protected:
  /// `transport` is a ModbusLink::Tcp or ModbusLink::Rtu; throws ConfigError on bad settings
  /// and ConnectionError when the instrument does not answer.
  template <class Transport>
  ModbusDriver(std::string instrument, const Transport& transport, const ModbusOptions& options,
               const InstrumentCapabilities& capabilities, std::uint16_t map_version)
      : link_(std::move(instrument), transport, options),
        capabilities_(capabilities),
        map_version_(map_version) {
    link_.open();
  }

  ModbusLink link_;

 private:
  const InstrumentCapabilities& capabilities_;  // static data of the register map
  std::uint16_t map_version_;
};

}  // namespace tocd::devices
