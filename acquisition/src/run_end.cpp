// The end of a run: the pin home (or stopped where it is), the chamber vented, the pollers
// stopped, every sample in the file, and the run's final status stored before anyone hears of
// its final state.
#include <fmt/format.h>

#include "pin_move.hpp"
#include "sequencer.hpp"
#include "tocd/core/log.hpp"

namespace tocd::acquisition {

void Sequencer::finish(Ending end) {
  if (end.state == EngineState::aborted) p_.events.emit("operator", "abort: " + end.why);
  try {
    set_state(EngineState::retracting, p_.control.step(), end.why);
    end_motion(end);
  } catch (const std::exception& e) {
    p_.events.emit("fault", fmt::format("while ending the run: {}", e.what()));
  }
  p_.pollers.stop_and_join();
  // Everything is in the file and the run has its final status before anyone hears of the
  // final state.
  p_.recorder.stop();
  account_for_lost_samples(end);
  store_final_status(end);
  set_state(end.state, p_.control.step(), end.why);
  p_.predictions.close();
}

void Sequencer::end_motion(const Ending& end) {
  if (TesterChannel* tester = p_.instruments.tester.get()) {
    if (tester->is_lost()) {
      p_.events.emit("fault", "the mechanical tester is unreachable: the pin could not be retracted");
    } else {
      tester->load_interlock().disarm();  // backing off lowers the load; do not stop the retraction
      retract(end.state != EngineState::interrupted || p_.setup.protocol.interlocks.retract_on_trip);
    }
  }
  if (p_.instruments.vacuum && p_.setup.protocol.kind == StepKind::vacuum) vent();
}

void Sequencer::retract(bool pin_home) {
  TesterChannel& tester = *p_.instruments.tester;
  const Protocol& protocol = p_.setup.protocol;
  const bool retract = pin_home && !p_.control.stopping_now();
  const std::uint64_t stop_cmd = tester.send_stop();
  if (tester.latest().limit_latched && retract) {
    // The tester stopped itself at its limit and refuses moves until cleared; backing off
    // only lowers the load.
    tester.send_clear_fault("clear the limit fault to retract");
  }
  if (!retract) {
    if (p_.control.stopping_now()) {
      wait_command(tester, stop_cmd, 2.0);
      stop_pin_at_once("not retracted");
    }
    return;
  }
  PinMove home;
  home.position_mm = 0.0;
  home.speed_mm_per_s = protocol.retract_speed_mm_per_s;
  home.interruptible = false;
  home.tolerance_mm = protocol.position_tolerance_mm;
  home.unknown_travel_mm = protocol.sample.thickness_mm + 10.0;
  home.timeout_margin_s = p_.options.move_timeout_margin_s;
  const MoveOutcome moved = move_pin(tester, home, *this);
  if (moved.result == MoveResult::arrived) return;
  if (p_.control.stopping_now()) {
    wait_command(tester, tester.send_stop(), 2.0);
    stop_pin_at_once("the retraction was cut short by a second abort");
  } else {
    p_.events.emit("fault", "pin did not reach home after the run; check the tester" +
                                (moved.problem.empty() ? std::string() : ": " + moved.problem));
  }
}

void Sequencer::stop_pin_at_once(const char* what) {
  p_.events.emit("operator", fmt::format("stopped at once: the pin is left at {:.4f} mm ({})",
                                         p_.instruments.tester->position_mm(), what));
}

void Sequencer::vent() {
  VacuumChannel& vacuum = *p_.instruments.vacuum;
  vacuum.seal_watch().disarm();
  vacuum.send_vent();
  // A few readings of the venting chamber end the run's pressure record.
  if (!p_.control.stopping_now())
    p_.pollers.sleep_for(p_.clock.real(3.0 / p_.setup.protocol.rates.pressure_Hz));
}

void Sequencer::account_for_lost_samples(Ending& end) {
  // A run whose samples did not all reach the file is not complete, even when every step was
  // (a commit that failed after the last step, or a full write queue).
  const db::WriterStats ws = p_.recorder.writer_stats();
  const std::uint64_t dropped = p_.recorder.dropped(), lost = dropped + ws.failed_samples;
  if (lost == 0 || end.state != EngineState::completed) return;
  end.state = EngineState::interrupted;
  end.why = fmt::format(
      "{} sample(s) were not stored ({} refused by the full write queue, {} lost to failed "
      "commits{}): the run's record is incomplete",
      lost, dropped, ws.failed_samples, ws.last_error.empty() ? "" : ": " + ws.last_error);
  p_.events.emit("fault", end.why);
}

void Sequencer::store_final_status(Ending& end) {
  if (end.state == EngineState::interrupted || end.state == EngineState::failed)
    p_.control.set_error(end.why);
  const db::RunStatus status = end.state == EngineState::completed ? db::RunStatus::completed
                               : end.state == EngineState::aborted ? db::RunStatus::aborted
                                                                   : db::RunStatus::interrupted;
  try {
    p_.db.set_run_status(p_.setup.run_id, status);
  } catch (const std::exception& e) {
    logger("acquisition")
        ->error("run {}: cannot set status {}: {}", p_.setup.run_id, db::to_string(status), e.what());
  }
}

}  // namespace tocd::acquisition
