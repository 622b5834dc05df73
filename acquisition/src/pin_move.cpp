#include "pin_move.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

namespace tocd::acquisition {

MoveOutcome move_pin(TesterChannel& tester, const PinMove& move, StepSequencer& sequencer) {
  MoveOutcome out;
  const double from = tester.position_mm();
  const double travel = std::isfinite(from) ? std::abs(move.position_mm - from) : move.unknown_travel_mm;
  const std::string what = fmt::format("move to {:.4f} mm at {} mm/s", move.position_mm, move.speed_mm_per_s);
  const std::uint64_t my_cmd = tester.send_move(what, move.position_mm, move.speed_mm_per_s);
  bool arrived = false;
  std::optional<std::string> failure;
  const auto settled = [&] {
    if (const auto outcome = tester.queue().outcome(my_cmd); outcome && !outcome->empty()) {
      failure = *outcome;
      return true;
    }
    const TesterSnapshot now = tester.latest();
    const double pos = now.displacement_mm + tester.contact_mm();
    arrived = now.commands_applied >= my_cmd && !now.moving &&
              std::abs(pos - move.position_mm) <= move.tolerance_mm;
    return arrived;
  };
  const double timeout = travel / move.speed_mm_per_s * 1.5 + move.timeout_margin_s;
  if (move.interruptible) {
    out.why = sequencer.wait_until(timeout, settled);
  } else {
    sequencer.wait_bounded(timeout, [&] { return settled() || tester.is_lost(); });
  }
  if (failure) {
    out.result = MoveResult::failed;
    out.problem = fmt::format("the mechanical tester did not carry out '{}': {}", what, *failure);
  } else if (arrived) {
    out.result = MoveResult::arrived;
  } else if (out.why != Interrupt::none) {
    out.result = MoveResult::interrupted;
  } else {
    const TesterSnapshot now = tester.latest();
    out.result = MoveResult::timed_out;
    out.problem =
        fmt::format("the mechanical tester did not reach {:.4f} mm within {} mm in time: at {:.4f} mm, {}",
                    move.position_mm, move.tolerance_mm, now.displacement_mm + tester.contact_mm(),
                    now.moving ? "still moving" : "stopped");
  }
  return out;
}

}  // namespace tocd::acquisition
