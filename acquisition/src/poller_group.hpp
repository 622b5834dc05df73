#pragma once

// The run's poller threads, one per instrument, and the stop signal that ends them. Whatever a
// poller throws becomes a logged error and a trip of the run, never std::terminate.

#include <thread>
#include <vector>

#include "instrument_channel.hpp"
#include "poller_context.hpp"

namespace tocd::acquisition {

class PollerGroup {
 public:
  PollerGroup(const ScaledClock& clock, RunEvents& events, FaultPolicy& faults, Recorder& recorder,
              double live_interval_s)
      : ctx_{clock, stop_, events, faults, recorder, live_interval_s} {}
  ~PollerGroup() { stop_and_join(); }
  PollerGroup(const PollerGroup&) = delete;
  PollerGroup& operator=(const PollerGroup&) = delete;

  /// Starts one poller for each instrument.
  void start(const std::vector<InstrumentChannel*>& instruments);
  /// Ends every poller's loop and waits for them (each first runs the commands still queued).
  void stop_and_join();
  /// Sleeps `d` (real time), or until the pollers are stopped.
  void sleep_for(std::chrono::nanoseconds d) const { stop_.sleep_for(d); }

 private:
  StopSignal stop_;
  PollerContext ctx_;
  std::vector<std::thread> threads_;
};

}  // namespace tocd::acquisition
