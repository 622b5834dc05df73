#pragma once

// One instrument of a run, as the engine holds it: its driver, the channels it reads (the
// driver's capability table), their recorder slots, and what the generic poller
// (instrument_poller.hpp) needs of it: its poll rate, whether the protocol uses it, its
// commands, one reading's meaning (`read`) and what losing it means (`lost`). Each kind
// (tester_channel.hpp, power_channel.hpp, vacuum_channel.hpp) adds its latest reading, kept
// as one snapshot under its own lock, and whatever else it owns (commands, interlock arming).
//
// Threads: configure() and set_slot() before the pollers start; read() and lost() on the
// instrument's poller only; the rest any thread.

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "command_queue.hpp"
#include "poller_context.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/devices/capabilities.hpp"

namespace tocd::acquisition {

class InstrumentChannel {
 public:
  explicit InstrumentChannel(const devices::InstrumentCapabilities& capabilities)
      : capabilities_(capabilities), slot_(capabilities.channels.size(), -1) {}
  virtual ~InstrumentChannel() = default;
  InstrumentChannel(const InstrumentChannel&) = delete;
  InstrumentChannel& operator=(const InstrumentChannel&) = delete;

  const devices::InstrumentCapabilities& capabilities() const noexcept { return capabilities_; }
  /// "mechanical tester": names it in events.
  std::string title() const { return std::string(capabilities_.title); }

  /// The poll rate (Hz of simulated time) and whether the protocol uses the instrument (the
  /// vacuum controller in a pin protocol does not: its faults are events only, they void no
  /// recording window, and losing it ends its polling, not the run).
  void configure(double rate_Hz, bool used) {
    rate_Hz_ = rate_Hz;
    used_ = used;
  }
  double rate_Hz() const noexcept { return rate_Hz_; }
  bool used() const noexcept { return used_; }

  /// The recorder slot of its channel `k` (the capability table's order).
  void set_slot(std::size_t k, int slot) { slot_.at(k) = slot; }
  int slot(std::size_t k) const { return slot_.at(k); }

  /// Commands for this driver; nullptr when it takes none during a run.
  virtual CommandQueue* commands() { return nullptr; }
  /// One reading: take it, record it, react to it. Throws when the instrument failed.
  /// `commands_run` is the number of the last command carried out before the reading.
  virtual void read(PollerContext& ctx, std::uint64_t commands_run, std::vector<LiveSample>& live) = 0;
  /// Its poller gave up on it (called once, before the run is tripped).
  virtual void lost() { lost_ = true; }
  bool is_lost() const noexcept { return lost_; }

 protected:
  /// Records `value` of channel `k`: into the run's samples and the live batch.
  void record(PollerContext& ctx, std::size_t k, std::int64_t t_ns, double value,
              std::vector<LiveSample>& live) {
    ctx.recorder.add(slot(k), t_ns, value);
    live.push_back({capabilities_.channels[k].name, t_ns, value});
  }

 private:
  const devices::InstrumentCapabilities& capabilities_;
  std::vector<int> slot_;
  double rate_Hz_ = 1;
  bool used_ = true;
  std::atomic<bool> lost_{false};  // written by its poller only
};

}  // namespace tocd::acquisition
