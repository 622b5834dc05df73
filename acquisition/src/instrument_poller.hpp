#pragma once

// The generic instrument poller: the one loop every instrument's thread runs. It is the only
// thread that talks to its driver: it runs the commands queued for the instrument, reads at the
// protocol's rate (pacing), tracks the instrument's faults (an event when they start and stop,
// a trip when they outlast the tolerance), and hands live readings to the observer in batches.
// What one reading means (samples, interlocks) is the instrument's own `read` step.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "command_queue.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

struct InstrumentPollerSpec {
  std::string instrument;            ///< "mechanical tester": names it in events
  double rate_Hz = 1;                ///< simulated time
  CommandQueue* commands = nullptr;  ///< commands for this driver; nullptr: it takes none
  /// One reading: take it, record it, react to it. Throws when the instrument failed.
  /// `commands_run` is the number of the last command carried out before the reading.
  std::function<void(std::uint64_t commands_run, std::vector<LiveSample>& live)> read;
  /// Called once when the poller gives up on the instrument (before the run is tripped).
  std::function<void()> lost;
  /// Whether the protocol uses this instrument (the vacuum controller in a pin protocol does
  /// not). The faults of one it does not use are events only: they void no recording window,
  /// and losing it ends its polling, not the run.
  bool used = true;
};

/// Runs the loop of `spec` on the calling thread until the pollers are stopped or the
/// instrument is lost.
void run_instrument_poller(Engine::Impl& m, const InstrumentPollerSpec& spec);

}  // namespace tocd::acquisition
