#pragma once

// The power meter of a run: its driver, its latest power (one value under its own lock), and
// what a reading means: over range first (the driver reports SCPI's 9.9E37 as +inf, which is no
// sample but a state of the meter that the protocol's interlock decides about), then
// implausible readings as failed reads.

#include <cmath>
#include <memory>
#include <mutex>

#include "instrument_channel.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition {

class PowerChannel final : public InstrumentChannel {
 public:
  explicit PowerChannel(std::unique_ptr<devices::PowerMeter> driver);

  /// The driver, for the calls made before the pollers start (identity, baseline).
  devices::PowerMeter& driver() { return *driver_; }
  /// The run's baseline power (W) and whether over range pauses it.
  void set_run(double baseline_W, bool over_range_pauses);

  double latest_W() const;

  void read(PollerContext& ctx, std::uint64_t commands_run, std::vector<LiveSample>& live) override;

 private:
  std::unique_ptr<devices::PowerMeter> driver_;
  double baseline_W_ = 0;
  bool over_range_pauses_ = true;

  mutable std::mutex mu_;  // guards latest_W_ only
  double latest_W_ = std::nan("");

  bool over_range_reported_ = false;  // the poller's own
};

}  // namespace tocd::acquisition
