#include "tester/tester_physics.hpp"

#include <algorithm>
#include <cmath>

#include "tocd/devices/tester_registers.hpp"

namespace tocd::mocks {

namespace m = tocd::devices::tester_map;

TesterPhysics::TesterPhysics(Params p) : p_(std::move(p)), rng_(p_.seed) {
  if (!p_.tissue) p_.tissue = make_analytic_tissue(2.5);
}

double TesterPhysics::true_load_N() const {
  if (displacement_mm() <= 0.0) return 0.0;  // the pin pushes, it cannot pull
  return std::max(0.0, p_.tissue->load_N(displacement_mm()) + overstress_N_);
}

double TesterPhysics::measured_load_N() {
  return true_load_N() + p_.load_cell_offset_N - tare_N_ + p_.load_noise_N * noise_(rng_);
}

void TesterPhysics::advance(double t_s) {
  double dt = t_s - t_s_;
  if (!(dt > 0.0)) return;
  t_s_ = t_s;
  if (!moving_) {  // holding: the overstress relaxes exactly, no need to step
    overstress_N_ *= std::exp(-dt / p_.relaxation_time_s);
    drain(dt);
    return;
  }
  // Moving: 1 ms (simulated) steps resolve the load limit to within one step of travel. No call
  // takes more than max_steps steps, though: a move may last for ever (any velocity above 0
  // is accepted, 1e-30 mm/s too), and a request after a long silence or at a large clock
  // factor would otherwise step through all the simulated time since, stalling the server
  // (found by the tester_modbus fuzz target). Longer steps then cover it.
  constexpr double max_steps = 1e4;
  const double longest = std::max(1e-3, dt / max_steps);
  while (dt > 0.0 && moving_) {
    const double h = std::min(dt, longest);
    step(h);
    dt -= h;
  }
  if (dt > 0.0) {
    overstress_N_ *= std::exp(-dt / p_.relaxation_time_s);
    drain(dt);
  }
}

void TesterPhysics::drain(double h) {
  const double d = displacement_mm();
  drained_displacement_ = d + (drained_displacement_ - d) * std::exp(-h / p_.drained_time_s);
}

void TesterPhysics::step(double h) {
  const double dist = target_ - position_;
  const double travel = velocity_ * h;
  if (std::abs(dist) <= travel) {
    position_ = target_;
    moving_ = false;
  } else {
    position_ += std::copysign(travel, dist);
  }
  // Standard linear solid: each increment of equilibrium load adds a fraction as overstress,
  // which decays with the relaxation time.
  const double eq = displacement_mm() > 0.0 ? p_.tissue->load_N(displacement_mm()) : 0.0;
  overstress_N_ = overstress_N_ * std::exp(-h / p_.relaxation_time_s) +
                  p_.relaxation_fraction * (eq - last_equilibrium_N_);
  last_equilibrium_N_ = eq;
  drain(h);
  if (dist > 0.0 && true_load_N() > p_.max_load_N) {  // only pressing further in trips the limit
    moving_ = false;
    fault_code_ = m::fault_load_limit;
  }
  // The travel limit holds during a move too (it may have been lowered after the move began):
  // the drive stops at it and latches the fault.
  if (dist > 0.0 && position_ > p_.max_travel_mm) {
    position_ = p_.max_travel_mm;
    moving_ = false;
    fault_code_ = m::fault_travel_limit;
  }
}

int TesterPhysics::move(double target_mm, double velocity) {
  if (fault_code_ != 0) return 4;
  if (!std::isfinite(target_mm) || target_mm < 0.0 || target_mm > p_.max_travel_mm) return 3;
  if (!std::isfinite(velocity) || velocity <= 0.0 || velocity > p_.max_velocity_mm_per_s) return 3;
  target_ = target_mm;
  velocity_ = velocity;
  moving_ = true;
  return 0;
}

int TesterPhysics::home() {
  if (fault_code_ != 0 && fault_code_ != m::fault_load_limit) return 4;
  target_ = 0.0;
  velocity_ = p_.home_velocity_mm_per_s;
  moving_ = position_ != 0.0;
  return 0;
}

void TesterPhysics::tare() {
  tare_N_ = true_load_N() + p_.load_cell_offset_N;
}

void TesterPhysics::clear_fault() {
  fault_code_ = m::fault_none;
}

bool TesterPhysics::limits_acceptable(double max_travel_mm, double max_load_N) const {
  return std::isfinite(max_travel_mm) && std::isfinite(max_load_N) && max_travel_mm > 0.0 &&
         max_load_N > 0.0 && max_travel_mm <= p_.travel_range_mm && max_load_N <= p_.load_capacity_N;
}

int TesterPhysics::set_limits(double max_travel_mm, double max_load_N) {
  if (!limits_acceptable(max_travel_mm, max_load_N)) return 3;
  p_.max_travel_mm = max_travel_mm;
  p_.max_load_N = max_load_N;
  return 0;
}

void TesterPhysics::trip_load_limit() {
  moving_ = false;
  fault_code_ = m::fault_load_limit;
}

void TesterPhysics::set_drive_fault(std::uint16_t code) {
  moving_ = false;
  fault_code_ = code;
}

}  // namespace tocd::mocks
