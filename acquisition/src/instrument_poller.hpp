#pragma once

// The generic instrument poller: the one loop every instrument's thread runs. It is the only
// thread that talks to its driver: it runs the commands queued for the instrument, reads at the
// protocol's rate (pacing), tracks the instrument's faults (an event when they start and stop,
// a trip when they outlast the tolerance), and hands live readings to the observer in batches.
// What one reading means (samples, interlocks) is the instrument channel's own `read`.

#include "instrument_channel.hpp"
#include "poller_context.hpp"

namespace tocd::acquisition {

/// Runs the loop of `instrument` on the calling thread until the pollers are stopped or the
/// instrument is lost.
void run_instrument_poller(PollerContext& ctx, InstrumentChannel& instrument);

}  // namespace tocd::acquisition
