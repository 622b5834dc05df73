#pragma once

// What a poller may use of the run, and nothing more: the run's clock, the stop signal that
// ends its sleeps, where its events and samples go, the fault policy, and how often the
// observer wants live readings.

#include "fault_policy.hpp"
#include "recorder.hpp"
#include "run_events.hpp"
#include "scaled_clock.hpp"
#include "stop_signal.hpp"

namespace tocd::acquisition {

struct PollerContext {
  const ScaledClock& clock;
  const StopSignal& stop;
  RunEvents& events;
  FaultPolicy& faults;
  Recorder& recorder;
  double live_interval_s = 0.05;  ///< real time between two batches of live readings
};

}  // namespace tocd::acquisition
