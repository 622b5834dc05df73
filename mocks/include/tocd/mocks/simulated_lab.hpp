#pragma once

#include <cstdint>
#include <memory>

#include "tocd/devices/lab.hpp"
#include "tocd/mocks/modbus_faults.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::mocks {

class SimClock;
class TesterTwin;
class PowerMeterTwin;
class VacuumTwin;

struct SimulatedLabOptions {
  std::shared_ptr<TissueModel> tissue;  ///< default: make_analytic_tissue(2.5)
  double clock_factor = 1.0;            ///< simulated seconds per real second
  double source_power_W = 1e-3;
  std::uint64_t seed = 1;
  double contact_position_mm = 1.0;
  bool with_vacuum = true;
  bool with_power_meter = true;
  /// Clearing over time: the share of a change in transmission that waits for the water to
  /// drain. The meter reads T = (1 - f) T(d) + f T(dd), d the pin's displacement and dd the
  /// tester's drained displacement (it follows d with delayed_clearing_time_s), so after a
  /// step T jumps by (1 - f) of the change and rises (or falls) the rest during the hold;
  /// at long holds T(d). 0: the sample clears at once.
  double delayed_clearing = 0.0;
  double delayed_clearing_time_s = 20.0;
  /// The sample's standard-linear-solid overstress (TesterTwinOptions).
  double relaxation_fraction = 0.3;
  double relaxation_time_s = 20.0;
  int tester_port = 0;       ///< 0 = any free port
  int power_meter_port = 0;  ///< 0 = any free port
};

/// Options whose sample behaves as `truth` says in time (relaxation, delayed clearing); the
/// tissue is left unset: make_default_sample(thickness, max displacement, truth) gives the one
/// with the truth's stiffness and optics.
SimulatedLabOptions simulated_lab_options(const SampleTruth& truth);

/// Every simulated instrument of the pin-compression rig, each on its real transport: the tester
/// (Modbus TCP on loopback), the power meter (SCPI over TCP) and the vacuum
/// controller (Modbus RTU on a pseudo-terminal). They share one clock and one tissue: the power
/// meter reads source power x transmission at the tester's current displacement (and, with
/// delayed clearing, at its drained displacement).
class SimulatedLab {
 public:
  explicit SimulatedLab(SimulatedLabOptions opt = {});
  ~SimulatedLab();  ///< stops all servers
  SimulatedLab(const SimulatedLab&) = delete;
  SimulatedLab& operator=(const SimulatedLab&) = delete;

  /// A lab config that points at the twins (short timeouts suited to loopback).
  tocd::devices::LabConfig config() const;

  const SimClock& clock() const;
  TesterTwin& tester();
  VacuumTwin* vacuum();  ///< null without vacuum
  bool has_power_meter() const;
  PowerMeterTwin* power_meter();  ///< null without power meter (all its fault hooks are there)

  // Fault hooks.
  void inject_tester_fault(const ModbusFault& fault);
  void inject_vacuum_fault(const ModbusFault& fault);
  void drop_tester_connections();
  void trip_load_limit();
  void inject_seal_loss(bool lost = true);
  /// Power meter faults; no-ops returning false while the lab has no power-meter twin.
  bool inject_power_meter_error(int code, const std::string& message);
  bool force_power_over_range(bool on);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::mocks
