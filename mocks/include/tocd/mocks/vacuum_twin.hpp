#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tocd/devices/modbus_options.hpp"
#include "tocd/mocks/modbus_faults.hpp"

namespace tocd::mocks {

class SimClock;

/// The pumped chamber as the twin's physics simulates it (mocks/src/vacuum/vacuum_physics.hpp):
/// first-order pump-down with a constant leak, bang-bang regulation at the setpoint, a vent
/// valve, and the controller's "setpoint not reached" error.
struct VacuumTwinPhysics {
  double atmosphere_kPa = 101.3;
  double ultimate_kPa = 0.5;          ///< best the pump reaches with no leak
  double pump_time_constant_s = 4.0;  ///< chamber volume / pumping speed
  double leak_kPa_per_s = 0.05;       ///< leak into the chamber (first-order pump-down with leak)
  double vent_time_constant_s = 0.5;
  double seal_loss_leak_kPa_per_s = 40.0;  ///< leak after inject_seal_loss()
  double setpoint_timeout_s = 60.0;        ///< pumping this long without reaching the setpoint = error 1
};

struct VacuumTwinOptions {
  std::shared_ptr<const SimClock> clock;  ///< default: a real-time clock
  int slave_id = 1;
  VacuumTwinPhysics physics;
};

/// The simulated vacuum pump controller: a libmodbus Modbus RTU server on the master side of a
/// pseudo-terminal pair (RS-232 mode), serving docs/instruments/vacuum-controller.md.
/// Clients open device_path() like a serial port. Thread-safe hooks.
class VacuumTwin {
 public:
  explicit VacuumTwin(VacuumTwinOptions options = {});
  ~VacuumTwin();
  VacuumTwin(const VacuumTwin&) = delete;
  VacuumTwin& operator=(const VacuumTwin&) = delete;

  const std::string& device_path() const;  ///< the slave side, e.g. /dev/pts/7
  devices::ModbusRtuAddress address() const;
  double pressure_kPa() const;

  // Fault hooks.
  void inject(const ModbusFault& fault);
  void inject_seal_loss(bool lost = true);  ///< the chamber seal leaks (or is fixed again)
  int faults_pending() const;

  /// Serves one frame as it would arrive on the serial line (slave id, PDU, CRC low byte
  /// first), on the caller's thread without the pseudo-terminal (for the fuzz targets and
  /// tests). Returns the answer frame; empty where the line stays silent: a frame shorter than
  /// 4 or longer than 256 bytes, a bad CRC, another slave's id, a broadcast. Not to be called
  /// from two threads at once.
  std::vector<std::uint8_t> serve_frame(std::span<const std::uint8_t> frame);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::mocks
