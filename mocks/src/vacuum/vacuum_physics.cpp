#include "vacuum/vacuum_physics.hpp"

#include <algorithm>
#include <cmath>

#include "tocd/devices/vacuum_registers.hpp"

namespace tocd::mocks {

VacuumPhysics::VacuumPhysics(Params p) : p_(p), p_kPa_(p.atmosphere_kPa) {}

void VacuumPhysics::advance(double t_s) {
  double dt = t_s - t_s_;
  if (!(dt > 0.0)) return;
  t_s_ = t_s;
  while (dt > 0.0) {  // 10 ms (simulated) steps: regulation and error timing to that grain
    const double h = std::min(dt, 0.01);
    step(h);
    dt -= h;
  }
}

void VacuumPhysics::step(double h) {
  const double leak = seal_lost_ ? p_.seal_loss_leak_kPa_per_s : p_.leak_kPa_per_s;
  const double atm = p_.atmosphere_kPa;
  if (vent_open_) {
    p_kPa_ = atm + (p_kPa_ - atm) * std::exp(-h / p_.vent_time_constant_s);
  } else if (pump_running() && p_kPa_ > setpoint_kPa_) {
    // dp/dt = -(p - p_ult)/tau + leak: exact over the step, toward p_ult + leak tau.
    const double tau = p_.pump_time_constant_s;
    const double p_eq = std::min(atm, p_.ultimate_kPa + leak * tau);
    p_kPa_ = p_eq + (p_kPa_ - p_eq) * std::exp(-h / tau);
  } else {
    p_kPa_ = std::min(atm, p_kPa_ + leak * h);
  }
  if (pump_running() && !vent_open_ && p_kPa_ > setpoint_kPa_ + 1.0) {
    above_setpoint_s_ += h;
    if (above_setpoint_s_ > p_.setpoint_timeout_s)
      error_code_ = devices::vacuum_map::err_setpoint_not_reached;
  } else {
    above_setpoint_s_ = 0.0;
  }
}

int VacuumPhysics::set_setpoint(double kPa) {
  if (!std::isfinite(kPa) || kPa <= 0.0 || kPa > p_.atmosphere_kPa) return 3;
  setpoint_kPa_ = kPa;
  return 0;
}

int VacuumPhysics::run_pump(bool on) {
  if (!on) {
    pump_on_ = false;
    error_code_ = 0;  // stopping the pump acknowledges an error
    above_setpoint_s_ = 0.0;
    return 0;
  }
  if (error_code_ != 0) return 4;
  pump_on_ = true;
  return 0;
}

}  // namespace tocd::mocks
