#pragma once

// What a fault does to the run. Every fault of an instrument the protocol uses is counted (a
// recording window during which the count moved is no measurement); a trip ends the run
// interrupted, a fault pause waits for the operator; an instrument that keeps failing longer
// than the tolerance is lost. Pollers, the sequencer and the thread guard reach the run's
// control for faults only through this part; its counters are atomics, any thread.

#include <atomic>
#include <cstdint>
#include <string>

#include "run_control.hpp"
#include "run_events.hpp"

namespace tocd::acquisition {

class FaultPolicy {
 public:
  FaultPolicy(RunControl& control, RunEvents& events, double tolerance_s)
      : control_(control), events_(events), tolerance_s_(tolerance_s) {}

  /// How long (simulated seconds) an instrument may keep failing before it is lost.
  double tolerance_s() const noexcept { return tolerance_s_; }

  /// A failed read, failed command or implausible reading; counted when the protocol uses the
  /// instrument.
  void count(bool used = true) noexcept {
    if (used) ++faults_;
  }
  std::uint64_t faults() const noexcept { return faults_; }
  /// A poller that fell far behind and skipped ahead.
  void overran() noexcept { ++overruns_; }
  std::uint64_t overruns() const noexcept { return overruns_; }

  /// An interlock trip: the run ends interrupted; the first trip is recorded as an event.
  void trip(const std::string& reason);
  /// A fault's pause: the first one is recorded as an event.
  void pause(const std::string& reason);
  /// A command an instrument did not carry out: an event and a fault.
  void command_failed(const std::string& instrument, const std::string& what, const std::string& error);

 private:
  RunControl& control_;
  RunEvents& events_;
  const double tolerance_s_;
  std::atomic<std::uint64_t> faults_{0}, overruns_{0};
};

}  // namespace tocd::acquisition
