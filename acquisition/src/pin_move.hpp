#pragma once

// A move of the pin and the wait for it to arrive. Arrived: the move was carried out (not
// refused), a reading taken after it says the pin has stopped, and that reading is within the
// protocol's tolerance of the target. A stopped pin anywhere else has not arrived, whatever the
// tester's at-target bit says.

#include <string>

#include "step_sequencer.hpp"
#include "tester_channel.hpp"

namespace tocd::acquisition {

/// How a move of the pin ended.
enum class MoveResult { arrived, failed, timed_out, interrupted };

struct PinMove {
  double position_mm = 0;     ///< from home
  double speed_mm_per_s = 1;  ///< > 0
  bool interruptible = true;  ///< false: only a stop at once cuts the wait short (the retraction)
  double tolerance_mm = 0;
  double unknown_travel_mm = 0;  ///< the travel assumed while the pin's position is not known
  double timeout_margin_s = 0;   ///< added to travel / speed x 1.5
};

struct MoveOutcome {
  MoveResult result = MoveResult::arrived;
  Interrupt why = Interrupt::none;  ///< what cut an interruptible move short
  std::string problem;              ///< why it failed or timed out
};

MoveOutcome move_pin(TesterChannel& tester, const PinMove& move, StepSequencer& sequencer);

}  // namespace tocd::acquisition
