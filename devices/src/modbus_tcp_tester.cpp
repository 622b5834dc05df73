// Mechanical tester over Modbus TCP (docs/instruments/mechanical-tester.md).
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "modbus/modbus_driver.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_driver.hpp"
#include "tocd/devices/tester_registers.hpp"

namespace tocd::devices {
namespace {

namespace m = tester_map;

class ModbusTcpTester final : public ModbusDriver<MechanicalTester> {
 public:
  ModbusTcpTester(const ModbusTcpAddress& a, const ModbusOptions& o)
      : ModbusDriver(fmt::format("mechanical tester {}:{}",
                                 a.host.find(':') == std::string::npos ? a.host : "[" + a.host + "]", a.port),
                     ModbusLink::Tcp{a}, o, m::capabilities, m::map_version) {}

  TesterReading read() override {
    // One transaction for position, load, status and fault code: the polling hot path.
    const PollBlock r = read_poll_block(link_, "position, load, status, fault code");
    TesterReading out;
    out.t_ns = monotonic_ns();
    out.position_mm = finite_float(link_, r, m::in_position, "position");
    out.load_N = finite_float(link_, r, m::in_load, "load");
    const std::uint16_t s = r[m::in_status];
    out.status.ready = s & m::st_ready;
    out.status.moving = s & m::st_moving;
    out.status.at_target = s & m::st_at_target;
    out.status.limit = s & m::st_limit;
    out.status.fault = s & m::st_fault;
    out.status.fault_code = r[m::in_fault_code];
    return out;
  }

  void move_to(double position_mm, double velocity_mm_per_s) override {
    if (!std::isfinite(position_mm) || !std::isfinite(velocity_mm_per_s) || velocity_mm_per_s <= 0.0)
      throw ConfigError(
          fmt::format("{}: move_to needs a finite target and a velocity > 0 (got {} mm, {} mm/s)",
                      link_.instrument(), position_mm, velocity_mm_per_s));
    // Target, velocity and the move command in one write: the move cannot start with stale values.
    const auto t = float_to_registers(static_cast<float>(position_mm));
    const auto v = float_to_registers(static_cast<float>(velocity_mm_per_s));
    const std::array<std::uint16_t, 5> regs{t[0], t[1], v[0], v[1], m::cmd_move};
    link_.write_registers(m::hr_target, 5, regs.data(), "target, velocity, move command");
  }

  void stop() override { command(m::cmd_stop, "stop command"); }
  void home() override { command(m::cmd_home, "home command"); }
  void tare_load() override { command(m::cmd_tare, "tare command"); }
  void clear_fault() override { command(m::cmd_clear_fault, "clear-fault command"); }

  void set_limits(double max_travel_mm, double max_load_N) override {
    if (!(max_travel_mm > 0.0) || !(max_load_N > 0.0) || !std::isfinite(max_travel_mm) ||
        !std::isfinite(max_load_N))
      throw ConfigError(fmt::format("{}: limits must be finite and > 0 (got {} mm, {} N)", link_.instrument(),
                                    max_travel_mm, max_load_N));
    const auto t = float_to_registers(static_cast<float>(max_travel_mm));
    const auto l = float_to_registers(static_cast<float>(max_load_N));
    const std::array<std::uint16_t, 4> regs{t[0], t[1], l[0], l[1]};
    link_.write_registers(m::hr_max_travel, 4, regs.data(), "travel and load limits");
  }

 private:
  void command(std::uint16_t code, const char* what) { link_.write_register(m::hr_command, code, what); }
};

}  // namespace

std::unique_ptr<MechanicalTester> connect_modbus_tcp_tester(const ModbusTcpAddress& address,
                                                            const ModbusOptions& options) {
  return std::make_unique<ModbusTcpTester>(address, options);
}

}  // namespace tocd::devices
