#pragma once

#include <cstdint>

#include "tocd/mocks/vacuum_twin.hpp"

namespace tocd::mocks {

/// The pumped chamber of VacuumTwinPhysics, without any protocol. Not thread-safe.
class VacuumPhysics {
 public:
  using Params = VacuumTwinPhysics;
  explicit VacuumPhysics(Params p);

  void advance(double t_s);

  int set_setpoint(double kPa);  ///< 0 or Modbus exception 3
  int run_pump(bool on);         ///< starting while in error: exception 4; stopping clears the error
  void set_vent(bool open) { vent_open_ = open; }
  void clear_error() { error_code_ = 0; }
  void set_seal_lost(bool lost) { seal_lost_ = lost; }

  double pressure_kPa() const { return p_kPa_; }
  double setpoint_kPa() const { return setpoint_kPa_; }
  bool pump_running() const { return pump_on_ && error_code_ == 0; }
  bool vent_open() const { return vent_open_; }
  bool at_setpoint() const { return pump_running() && !vent_open_ && p_kPa_ <= setpoint_kPa_ + 1.0; }
  std::uint16_t error_code() const { return error_code_; }

 private:
  void step(double h);

  Params p_;
  double t_s_ = 0.0;
  double p_kPa_;
  double setpoint_kPa_ = 5.0;
  bool pump_on_ = false, vent_open_ = false, seal_lost_ = false;
  double above_setpoint_s_ = 0.0;
  std::uint16_t error_code_ = 0;
};

}  // namespace tocd::mocks
