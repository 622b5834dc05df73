#pragma once

// The mechanical tester of a run: its driver, its latest reading (one snapshot under its own
// lock: position, load, status bits and how many commands it had carried out, taken together),
// its command queue, its load interlock's arming, the load's settle window, and whether its
// poller gave up on it.

#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "instrument_channel.hpp"
#include "interlock_arming.hpp"
#include "rate_window.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition {

/// One reading of the tester as the engine keeps it.
struct TesterSnapshot {
  double displacement_mm = std::nan("");  ///< position - contact position
  double load_N = std::nan("");
  bool moving = false;
  bool at_target = false;
  bool limit_latched = false;          ///< the tester reports its limit tripped
  std::uint64_t commands_applied = 0;  ///< the reading was taken after this many commands
};

class TesterChannel final : public InstrumentChannel {
 public:
  explicit TesterChannel(std::unique_ptr<devices::MechanicalTester> driver);

  /// The driver, for the calls made before the pollers start (identity, tare, limits) or
  /// after they stopped; while they run only the poller talks to it (through commands()).
  devices::MechanicalTester& driver() { return *driver_; }

  /// The run's contact position (mm) and load limit (N).
  void set_run(double contact_position_mm, double max_load_N, double settle_keep_s);

  TesterSnapshot latest() const;
  /// Position of the pin (mm from home) in the latest reading.
  double position_mm() const { return latest().displacement_mm + contact_mm_; }
  double contact_mm() const noexcept { return contact_mm_; }

  CommandQueue* commands() override { return &commands_; }
  CommandQueue& queue() { return commands_; }
  /// Queues a stop; returns its command number.
  std::uint64_t send_stop();
  /// Queues a move (`what` names it in events); returns its command number.
  std::uint64_t send_move(std::string what, double position_mm, double speed_mm_per_s);
  /// Queues the clearing of a latched limit (`why` names it in events).
  void send_clear_fault(std::string why);
  InterlockArming& load_interlock() { return interlock_; }
  RateWindow& load_window() { return load_window_; }

  void read(PollerContext& ctx, std::uint64_t commands_run, std::vector<LiveSample>& live) override;
  void lost() override;

 private:
  /// Why the reading trips the load interlock ("" when it does not).
  std::string interlock_reason(const devices::TesterReading& r, double displacement_mm);

  std::unique_ptr<devices::MechanicalTester> driver_;
  double contact_mm_ = 0;
  double max_load_N_ = 0;
  CommandQueue commands_;
  InterlockArming interlock_{true};
  RateWindow load_window_;

  mutable std::mutex mu_;  // guards latest_ only
  TesterSnapshot latest_;

  // The poller's own: the arming it has acted on, and whether it reported the limit bit.
  std::uint64_t tripped_arming_ = 0;
  bool limit_reported_ = false;
};

}  // namespace tocd::acquisition
