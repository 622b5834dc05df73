#pragma once

// What differs between pin-compression and vacuum steps, for the sequencer's phases: how a
// step's target is approached, which reading shows the sample settled, what the step row
// records as its target, and what becomes of a recorded step. Each strategy holds its
// instrument channel and the small StepSequencer interface of the sequencer that runs it.

#include <memory>
#include <optional>
#include <string>

#include "prediction_queue.hpp"
#include "rate_window.hpp"
#include "run_setup.hpp"
#include "step_sequencer.hpp"
#include "tester_channel.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/db/records.hpp"

namespace tocd::acquisition {

class VacuumChannel;

class StepStrategy {
 public:
  virtual ~StepStrategy() = default;
  /// "pin to 0.5 mm", for the moving state.
  virtual std::string target_text(const ProtocolStep& step) const = 0;
  /// The move phase: the pin to its position, or the chamber to its setpoint. Returns why it
  /// was cut short (Interrupt::none: at the target).
  virtual Interrupt approach(const ProtocolStep& step) = 0;
  /// The readings whose rate of change says the sample has settled, and their unit.
  virtual RateWindow& settle_window() = 0;
  virtual const char* settle_unit() const = 0;
  virtual void set_targets(const ProtocolStep& step, db::StepRecord& rec) const = 0;
  /// Where the recording window must find the pin (pin steps only).
  virtual std::optional<double> target_displacement_mm(const ProtocolStep& step) const = 0;
  /// A step stored as completed: pin steps go to the predictor.
  virtual void recorded(const StepResult& result) = 0;
};

/// Pin steps: each recorded step goes to `predictions`.
std::unique_ptr<StepStrategy> make_pin_steps(TesterChannel& tester, StepSequencer& sequencer,
                                             const RunSetup& setup, double move_timeout_margin_s,
                                             PredictionQueue& predictions);
/// Vacuum steps: the setpoint is reached within `reached_kPa`, waited for at most
/// `max_wait_s` (simulated).
std::unique_ptr<StepStrategy> make_vacuum_steps(VacuumChannel& vacuum, StepSequencer& sequencer,
                                                double max_wait_s, double reached_kPa);

}  // namespace tocd::acquisition
