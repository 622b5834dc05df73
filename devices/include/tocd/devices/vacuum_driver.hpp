#pragma once

#include <memory>

#include "tocd/devices/instruments.hpp"
#include "tocd/devices/modbus_options.hpp"

namespace tocd::devices {

/// Connects to a vacuum pump controller speaking the tocdlab vacuum register map
/// (docs/instruments/vacuum-controller.md) over Modbus RTU. Throws ConnectionError when the
/// serial device cannot be opened.
std::unique_ptr<VacuumController> connect_modbus_rtu_vacuum(const ModbusRtuAddress& address,
                                                            const ModbusOptions& options = {});

}  // namespace tocd::devices
