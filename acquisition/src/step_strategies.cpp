// Pin-compression and vacuum steps (step_strategy.hpp).
#include <cmath>

#include <fmt/format.h>

#include "pin_move.hpp"
#include "step_strategy.hpp"
#include "vacuum_channel.hpp"

namespace tocd::acquisition {

namespace {

class PinSteps final : public StepStrategy {
 public:
  PinSteps(TesterChannel& tester, StepSequencer& sequencer, const RunSetup& setup, double margin_s,
           PredictionQueue& predictions)
      : tester_(tester),
        sequencer_(sequencer),
        setup_(setup),
        margin_s_(margin_s),
        predictions_(predictions) {}
  std::string target_text(const ProtocolStep& step) const override {
    return fmt::format("pin to {} mm", step.displacement_mm);
  }
  Interrupt approach(const ProtocolStep& step) override {
    const Protocol& p = setup_.protocol;
    PinMove move;
    move.position_mm = p.contact_position_mm + step.displacement_mm;
    move.speed_mm_per_s = p.approach_speed_mm_per_s;
    move.tolerance_mm = p.position_tolerance_mm;
    move.unknown_travel_mm = p.sample.thickness_mm + 10.0;
    move.timeout_margin_s = margin_s_;
    const MoveOutcome moved = move_pin(tester_, move, sequencer_);
    if (moved.result == MoveResult::interrupted) return moved.why;
    if (moved.result != MoveResult::arrived) return sequencer_.move_failed(step, moved.problem);
    return Interrupt::none;
  }
  RateWindow& settle_window() override { return tester_.load_window(); }
  const char* settle_unit() const override { return "N"; }
  void set_targets(const ProtocolStep& step, db::StepRecord& rec) const override {
    rec.target_displacement_mm = step.displacement_mm;
    rec.nominal_strain = step.nominal_strain;
  }
  std::optional<double> target_displacement_mm(const ProtocolStep& step) const override {
    return step.displacement_mm;
  }
  void recorded(const StepResult& r) override {
    // The model is asked about the displacement the window measured, not the one it aimed at.
    predictions_.push({setup_.run_id, r.index, r.measured_displacement_mm,
                       setup_.protocol.sample.thickness_mm, r.load_N, r.measured_T});
  }

 private:
  TesterChannel& tester_;
  StepSequencer& sequencer_;
  const RunSetup& setup_;
  double margin_s_;
  PredictionQueue& predictions_;
};

class VacuumSteps final : public StepStrategy {
 public:
  VacuumSteps(VacuumChannel& vacuum, StepSequencer& sequencer, double max_wait_s, double reached_kPa)
      : vacuum_(vacuum), sequencer_(sequencer), max_wait_s_(max_wait_s), reached_kPa_(reached_kPa) {}
  std::string target_text(const ProtocolStep& step) const override {
    return fmt::format("vacuum to {} kPa", step.pressure_kPa);
  }
  Interrupt approach(const ProtocolStep& step) override {
    vacuum_.seal_watch().disarm();
    const double p = step.pressure_kPa;
    vacuum_.send_setpoint(p);
    bool reached = false;
    const Interrupt why = sequencer_.wait_until(max_wait_s_, [&] {
      reached = std::abs(vacuum_.latest_kPa() - p) <= reached_kPa_;
      return reached;
    });
    if (why != Interrupt::none) return why;
    if (!reached) {
      sequencer_.trip(fmt::format("vacuum did not reach {} kPa (last {:.2f} kPa)", p, vacuum_.latest_kPa()));
      return Interrupt::trip;
    }
    vacuum_.seal_watch().arm(p);
    return Interrupt::none;
  }
  RateWindow& settle_window() override { return vacuum_.pressure_window(); }
  const char* settle_unit() const override { return "kPa"; }
  void set_targets(const ProtocolStep& step, db::StepRecord& rec) const override {
    rec.target_pressure_kPa = step.pressure_kPa;
  }
  std::optional<double> target_displacement_mm(const ProtocolStep&) const override { return std::nullopt; }
  void recorded(const StepResult&) override {}  // the simulator models pin compression only

 private:
  VacuumChannel& vacuum_;
  StepSequencer& sequencer_;
  double max_wait_s_;
  double reached_kPa_;
};

}  // namespace

std::unique_ptr<StepStrategy> make_pin_steps(TesterChannel& tester, StepSequencer& sequencer,
                                             const RunSetup& setup, double move_timeout_margin_s,
                                             PredictionQueue& predictions) {
  return std::make_unique<PinSteps>(tester, sequencer, setup, move_timeout_margin_s, predictions);
}

std::unique_ptr<StepStrategy> make_vacuum_steps(VacuumChannel& vacuum, StepSequencer& sequencer,
                                                double max_wait_s, double reached_kPa) {
  return std::make_unique<VacuumSteps>(vacuum, sequencer, max_wait_s, reached_kPa);
}

}  // namespace tocd::acquisition
