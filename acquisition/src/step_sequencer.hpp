#pragma once

// What a step strategy may ask of the sequencer that runs it: waits that requests (pause,
// abort, trip) cut short, a bounded wait that only a stop at once cuts short, and what to do
// when a move fails or the step cannot go on.

#include <functional>
#include <string>

#include "run_control.hpp"
#include "tocd/acquisition/protocol.hpp"

namespace tocd::acquisition {

class StepSequencer {
 public:
  /// Waits at most `max_sim_s` (simulated) for `done` (null: the whole time); a pause, abort
  /// or trip ends it early and is returned (Interrupt::none: done, or the time ran out).
  virtual Interrupt wait_until(double max_sim_s, const std::function<bool()>& done) = 0;
  /// Waits at most `max_sim_s` for `done`; only a stop at once ends it early.
  virtual void wait_bounded(double max_sim_s, const std::function<bool()>& done) = 0;
  /// A move of `step` that failed or timed out: the run pauses or ends interrupted, as the
  /// protocol says; returns which.
  virtual Interrupt move_failed(const ProtocolStep& step, const std::string& problem) = 0;
  virtual void trip(const std::string& reason) = 0;

 protected:
  ~StepSequencer() = default;
};

}  // namespace tocd::acquisition
