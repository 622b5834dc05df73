// Vacuum pump controller over Modbus RTU (docs/instruments/vacuum-controller.md).
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "modbus/modbus_driver.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/vacuum_driver.hpp"
#include "tocd/devices/vacuum_registers.hpp"

namespace tocd::devices {
namespace {

namespace vm = vacuum_map;

class ModbusRtuVacuum final : public ModbusDriver<VacuumController> {
 public:
  ModbusRtuVacuum(const ModbusRtuAddress& a, const ModbusOptions& o)
      : ModbusDriver(fmt::format("vacuum controller {} (slave {})", a.device, a.slave_id), ModbusLink::Rtu{a},
                     o, vm::capabilities, vm::map_version) {}

  VacuumReading read() override {
    const PollBlock r = read_poll_block(link_, "pressure, setpoint, status, error code");
    VacuumReading out;
    out.t_ns = monotonic_ns();
    out.pressure_kPa = registers_to_float(r[vm::in_pressure], r[vm::in_pressure + 1]);
    // An absolute pressure: a negative one is as wrong as a NaN.
    if (!std::isfinite(out.pressure_kPa) || out.pressure_kPa < 0.0)
      throw ProtocolError(link_.instrument(), "read of input registers 0..1 (pressure)",
                          fmt::format("the pressure is not a finite number >= 0 (got {})", out.pressure_kPa));
    out.setpoint_kPa = finite_float(link_, r, vm::in_setpoint, "setpoint");
    out.pump_running = r[vm::in_status] & vm::st_pump_running;
    out.vent_open = r[vm::in_status] & vm::st_vent_open;
    out.error_code = r[vm::in_error_code];
    return out;
  }

  void set_setpoint_kPa(double kPa) override {
    if (!std::isfinite(kPa) || kPa <= 0.0)
      throw ConfigError(fmt::format("{}: the setpoint must be a finite absolute pressure > 0 kPa (got {})",
                                    link_.instrument(), kPa));
    const auto regs = float_to_registers(static_cast<float>(kPa));
    link_.write_registers(vm::hr_setpoint, 2, regs.data(), "setpoint");
  }

  void run_pump(bool on) override { link_.write_register(vm::hr_pump_run, on ? 1 : 0, "pump run"); }
  void set_vent(bool open) override { link_.write_register(vm::hr_vent, open ? 1 : 0, "vent valve"); }
};

}  // namespace

std::unique_ptr<VacuumController> connect_modbus_rtu_vacuum(const ModbusRtuAddress& address,
                                                            const ModbusOptions& options) {
  return std::make_unique<ModbusRtuVacuum>(address, options);
}

}  // namespace tocd::devices
