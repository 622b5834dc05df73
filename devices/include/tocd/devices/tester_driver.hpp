#pragma once

#include <memory>

#include "tocd/devices/instruments.hpp"
#include "tocd/devices/modbus_options.hpp"

namespace tocd::devices {

/// Connects to a mechanical tester speaking the tocdlab tester register map
/// (docs/instruments/mechanical-tester.md) over Modbus TCP. Throws ConnectionError when the
/// first connection cannot be made within the options' timeout and retries.
std::unique_ptr<MechanicalTester> connect_modbus_tcp_tester(const ModbusTcpAddress& address,
                                                            const ModbusOptions& options = {});

}  // namespace tocd::devices
