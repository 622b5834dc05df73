#pragma once

#include <cstdint>
#include <string>

#include "tocd/devices/capabilities.hpp"
#include "tocd/devices/errors.hpp"

namespace tocd::devices {

/// Who an instrument says it is (stored with every run).
struct Identity {
  std::string vendor;
  std::string model;
  std::string serial;
  std::string firmware;
  friend bool operator==(const Identity&, const Identity&) = default;
};

/// What every instrument driver answers, whatever the instrument measures.
class Instrument {
 public:
  virtual ~Instrument() = default;
  /// The channels this driver reads (its capability table); static data, any thread.
  virtual const InstrumentCapabilities& describe() const = 0;
  virtual Identity identity() = 0;
};

/// Status bits of the mechanical tester.
struct TesterStatus {
  bool ready = false;
  bool moving = false;
  bool at_target = false;
  bool limit = false;  ///< travel or load limit tripped
  bool fault = false;
  std::uint16_t fault_code = 0;
};

/// One reading of the tester: pin position (mm, positive = pin moving down into the sample,
/// 0 = home) and load (N, positive = compressive), taken in one transaction.
struct TesterReading {
  double position_mm = 0.0;
  double load_N = 0.0;
  TesterStatus status;
  std::int64_t t_ns = 0;  ///< monotonic timestamp when the answer arrived
};

/// The servo-electric load frame that drives the pin. Drivers bound every wait and raise
/// DeviceError subclasses; they are not thread-safe (one poller owns one driver).
class MechanicalTester : public Instrument {
 public:
  virtual TesterReading read() = 0;
  /// Starts a move to `position_mm` at `velocity_mm_per_s`; returns at once (poll read()).
  virtual void move_to(double position_mm, double velocity_mm_per_s) = 0;
  virtual void stop() = 0;
  virtual void home() = 0;
  virtual void tare_load() = 0;
  virtual void set_limits(double max_travel_mm, double max_load_N) = 0;
  virtual void clear_fault() = 0;
};

/// One optical power reading (W).
struct PowerReading {
  double power_W = 0.0;
  bool over_range = false;
  std::int64_t t_ns = 0;
};

/// The optical power meter under the glass slide (USBTMC or SCPI over TCP).
class PowerMeter : public Instrument {
 public:
  virtual std::string sensor_identity() = 0;
  virtual void set_wavelength_nm(double nm) = 0;
  virtual void set_auto_range(bool on) = 0;
  virtual void set_averaging(int count) = 0;
  /// Dark-current zeroing; blocks (bounded) until the meter reports it finished.
  virtual void zero() = 0;
  virtual PowerReading measure() = 0;
};

/// One reading of the vacuum pump controller.
struct VacuumReading {
  double pressure_kPa = 0.0;  ///< absolute
  double setpoint_kPa = 0.0;
  bool pump_running = false;
  bool vent_open = false;
  std::uint16_t error_code = 0;
  std::int64_t t_ns = 0;
};

/// The vacuum pump controller of a TOCD (Modbus RTU on a serial line).
class VacuumController : public Instrument {
 public:
  virtual VacuumReading read() = 0;
  virtual void set_setpoint_kPa(double kPa) = 0;
  virtual void run_pump(bool on) = 0;
  virtual void set_vent(bool open) = 0;
};

}  // namespace tocd::devices
