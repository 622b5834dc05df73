#pragma once

#include <cstdint>
#include <memory>
#include <random>

#include "tocd/mocks/tester_twin.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::mocks {

/// The load frame and its sample, without any protocol: finite-speed motion of the pin, load
/// from the tissue's equilibrium curve plus a standard-linear-solid overstress that relaxes while
/// the pin holds, load-cell offset and noise, travel and load limits. Not thread-safe.
///
/// The overstress is what a biphasic sample carries while its water has not yet drained; a
/// first-order drainage gives the drained displacement: the displacement whose water content
/// the sample has reached (it follows the pin's displacement, d(dd)/dt = (d - dd) /
/// drained_time_s). The simulated lab's delayed clearing reads it. Both time constants are the
/// sample's truth (sample_truth.hpp); by default they are equal.
class TesterPhysics {
 public:
  using Params = TesterTwinPhysics;
  explicit TesterPhysics(Params p);

  /// Advance to simulated time t (s); earlier times are ignored.
  void advance(double t_s);

  // Commands; they return 0 or the Modbus exception code that refuses them.
  int move(double target_mm, double velocity_mm_per_s);
  int home();
  void stop() { moving_ = false; }
  void tare();
  void clear_fault();
  int set_limits(double max_travel_mm, double max_load_N);
  /// Finite, positive and within the travel range and the load cell's capacity.
  bool limits_acceptable(double max_travel_mm, double max_load_N) const;
  void trip_load_limit();
  void set_drive_fault(std::uint16_t code);

  double position_mm() const { return position_; }
  double displacement_mm() const { return std::max(0.0, position_ - p_.contact_position_mm); }
  double drained_displacement_mm() const { return drained_displacement_; }
  double true_load_N() const;  ///< what the sample pushes back with
  double measured_load_N();    ///< what the load cell reports (offset, tare, noise)
  bool moving() const { return moving_; }
  bool at_target() const { return !moving_ && std::abs(position_ - target_) < 1e-6; }
  bool limit() const { return fault_code_ == 1 || fault_code_ == 2; }
  std::uint16_t fault_code() const { return fault_code_; }
  double max_travel_mm() const { return p_.max_travel_mm; }
  double max_load_N() const { return p_.max_load_N; }

 private:
  void step(double h);
  void drain(double h);  ///< the drained displacement follows the displacement over h seconds

  Params p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  double t_s_ = 0.0;
  double position_ = 0.0, target_ = 0.0, velocity_ = 1.0;
  bool moving_ = false;
  double overstress_N_ = 0.0;
  double drained_displacement_ = 0.0;
  double last_equilibrium_N_ = 0.0;
  double tare_N_ = 0.0;
  std::uint16_t fault_code_ = 0;
};

}  // namespace tocd::mocks
