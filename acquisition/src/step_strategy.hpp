#pragma once

// What differs between pin-compression and vacuum steps, for the sequencer's phases: how a
// step's target is approached, which reading shows the sample settled, what the step row
// records as its target, and what becomes of a recorded step.

#include <memory>
#include <optional>
#include <string>

#include "rate_window.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/db/records.hpp"

namespace tocd::acquisition {

enum class Interrupt;

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

std::unique_ptr<StepStrategy> make_pin_steps(Engine::Impl& engine);
std::unique_ptr<StepStrategy> make_vacuum_steps(Engine::Impl& engine);

}  // namespace tocd::acquisition
