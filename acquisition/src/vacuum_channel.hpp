#pragma once

// The vacuum controller of a run: its driver, its latest pressure (one value under its own
// lock), its command queue, the pressure's settle window, and the seal watch: armed by the
// sequencer once a step's setpoint is reached (its one writer), checked by the poller, which
// pauses the run once per arming when the pressure rises beyond the allowed loss.

#include <cmath>
#include <memory>
#include <mutex>

#include "instrument_channel.hpp"
#include "interlock_arming.hpp"
#include "rate_window.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition {

class VacuumChannel final : public InstrumentChannel {
 public:
  explicit VacuumChannel(std::unique_ptr<devices::VacuumController> driver);

  /// The driver, for the calls made before the pollers start (identity).
  devices::VacuumController& driver() { return *driver_; }
  /// The pressure rise (kPa) over the setpoint that is a seal loss.
  void set_run(double vacuum_loss_kPa, double settle_keep_s);

  double latest_kPa() const;

  CommandQueue* commands() override { return &commands_; }
  CommandQueue& queue() { return commands_; }
  /// Queues pump on toward `setpoint_kPa` (vent closed).
  void send_setpoint(double setpoint_kPa);
  /// Queues pump off and vent open.
  void send_vent();
  InterlockArming& seal_watch() { return seal_watch_; }
  RateWindow& pressure_window() { return pressure_window_; }

  void read(PollerContext& ctx, std::uint64_t commands_run, std::vector<LiveSample>& live) override;

 private:
  std::unique_ptr<devices::VacuumController> driver_;
  double loss_kPa_ = 0;
  CommandQueue commands_;
  InterlockArming seal_watch_{false};
  RateWindow pressure_window_;

  mutable std::mutex mu_;  // guards latest_kPa_ only
  double latest_kPa_ = std::nan("");

  std::uint64_t reported_arming_ = 0;  // the poller's own
};

}  // namespace tocd::acquisition
