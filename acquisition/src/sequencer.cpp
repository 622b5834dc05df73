// The sequencer: runs the protocol's steps in explicit phases (move, settle, hold, record;
// what differs between pin and vacuum steps is the StepStrategy's), reacts to pause, abort and
// interlock trips, and ends the run.
#include <cmath>
#include <limits>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine_impl.hpp"
#include "step_strategy.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"
#include "window_check.hpp"

namespace tocd::acquisition {

Interrupt Engine::Impl::wait_until(double max_sim_s, const std::function<bool()>& done) {
  const std::int64_t real_end = monotonic_ns() + clock.real(max_sim_s).count();
  std::int64_t next_progress = 0;
  for (;;) {
    if (done && done()) return Interrupt::none;
    const std::int64_t now = monotonic_ns();
    if (observer && now >= next_progress) {
      notify([&](EngineObserver& o) { o.on_progress(make_progress()); });
      next_progress = now + static_cast<std::int64_t>(opt.progress_interval_s * 1e9);
    }
    if (now >= real_end) return Interrupt::none;
    // Short waits: the done() condition is polled, requests wake us at once.
    const auto slice = std::min<std::int64_t>(real_end - now, done ? 2'000'000 : 20'000'000);
    if (const auto i = control.wait_for_request(std::chrono::nanoseconds(slice)); i != Interrupt::none)
      return i;
  }
}

std::uint64_t Engine::Impl::send_tester(std::string what, std::function<void()> cmd) {
  return tester_cmds.push(std::move(what), std::move(cmd));
}

void Engine::Impl::send_vacuum(std::string what, std::function<void()> cmd) {
  vacuum_cmds.push(std::move(what), std::move(cmd));
}

bool Engine::Impl::wait_command(const CommandQueue& q, std::uint64_t id, double max_real_s) {
  const std::int64_t end = monotonic_ns() + static_cast<std::int64_t>(max_real_s * 1e9);
  while (!q.outcome(id) && !tester_lost && !control.stopping_now() && monotonic_ns() < end) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return q.outcome(id).has_value();
}

MoveResult Engine::Impl::move_and_wait(double position_mm, double speed_mm_per_s, bool interruptible,
                                       Interrupt& why, std::string& problem) {
  why = Interrupt::none;
  const double from = latest[kDisplacement] + protocol.contact_position_mm;
  const double travel =
      std::isfinite(from) ? std::abs(position_mm - from) : protocol.sample.thickness_mm + 10.0;
  const std::string what = fmt::format("move to {:.4f} mm at {} mm/s", position_mm, speed_mm_per_s);
  const std::uint64_t my_cmd = send_tester(
      what, [this, position_mm, speed_mm_per_s] { inst.tester->move_to(position_mm, speed_mm_per_s); });
  // Arrived: the move was carried out (not refused), a reading taken after it says the pin has
  // stopped, and that reading is within the protocol's tolerance of the target. A stopped pin
  // anywhere else has not arrived, whatever the tester's at-target bit says.
  bool arrived = false;
  std::optional<std::string> failure;
  const auto settled_fn = [&] {
    if (const auto outcome = tester_cmds.outcome(my_cmd); outcome && !outcome->empty()) {
      failure = *outcome;
      return true;
    }
    const double pos = latest[kDisplacement] + protocol.contact_position_mm;
    arrived = tester_commands_applied >= my_cmd && !tester_moving &&
              std::abs(pos - position_mm) <= protocol.position_tolerance_mm;
    return arrived;
  };
  const double timeout = travel / speed_mm_per_s * 1.5 + opt.move_timeout_margin_s;
  if (interruptible) {
    why = wait_until(timeout, settled_fn);
  } else {
    const std::int64_t end = monotonic_ns() + clock.real(timeout).count();
    while (!settled_fn() && !control.stopping_now() && !tester_lost && monotonic_ns() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (failure) {
    problem = fmt::format("the mechanical tester did not carry out '{}': {}", what, *failure);
    return MoveResult::failed;
  }
  if (arrived) return MoveResult::arrived;
  if (why != Interrupt::none) return MoveResult::interrupted;
  const double pos = latest[kDisplacement] + protocol.contact_position_mm;
  problem = fmt::format(
      "the mechanical tester did not reach {:.4f} mm within {} mm in time: at {:.4f} mm, {}", position_mm,
      protocol.position_tolerance_mm, pos, tester_moving ? "still moving" : "stopped");
  return MoveResult::timed_out;
}

Interrupt Engine::Impl::move_failed(const ProtocolStep& step, const std::string& problem) {
  const std::string why = fmt::format("step {}: {}", step.index + 1, problem);
  if (protocol.interrupt_on_move_failure) {
    trip(why);
    return Interrupt::trip;
  }
  request_pause(why);
  return Interrupt::pause;
}

Interrupt Engine::Impl::step_incomplete(const ProtocolStep& step, const std::string& problem) {
  const std::string why = fmt::format("step {} not recorded after {} recording(s): {}", step.index + 1,
                                      protocol.max_rerecords + 1, problem);
  request_pause(why);
  return Interrupt::pause;
}

// One step: move -> settle -> hold -> record, each phase below; a window that is not a
// measurement sends the step back to its move (bounded), or leaves it without a row.
Interrupt Engine::Impl::run_step(const ProtocolStep& step) {
  const int n = static_cast<int>(protocol.steps.size());
  for (int attempt = 0;; ++attempt) {
    db::StepRecord rec;
    rec.run_id = run_id;
    rec.index = step.index;
    rec.started_t_ns = clock.now_ns();
    steps->set_targets(step, rec);
    set_state(EngineState::moving,
              fmt::format("step {}/{}: {}", step.index + 1, n, steps->target_text(step)));
    if (const Interrupt why = steps->approach(step); why != Interrupt::none) return why;
    bool settled = false;
    if (const Interrupt why = settle_phase(step, rec, settled); why != Interrupt::none) return why;
    if (const Interrupt why = hold_phase(); why != Interrupt::none) return why;
    WindowObservation seen;
    if (const Interrupt why = record_phase(rec, seen); why != Interrupt::none) return why;
    // Only a window that holds up is a measurement; otherwise record it again, or leave the
    // step without a row and pause.
    if (const std::string problem = window_problem(step, seen); !problem.empty()) {
      if (attempt >= protocol.max_rerecords) return step_incomplete(step, problem);
      emit_event(
          "step",
          fmt::format("step {}: recording window is not a measurement ({}); recording it again ({} of {})",
                      step.index + 1, problem, attempt + 1, protocol.max_rerecords),
          step.index);
      continue;
    }
    store_step(step, rec, seen, settled);
    return Interrupt::none;
  }
}

Interrupt Engine::Impl::settle_phase(const ProtocolStep& step, db::StepRecord& rec, bool& settled) {
  set_state(EngineState::settling, "");
  const std::int64_t settle_from = clock.now_ns();
  RateWindow& window = steps->settle_window();
  double last_rate = std::numeric_limits<double>::quiet_NaN();
  const Interrupt why = wait_until(protocol.settle.max_wait_s, [&] {
    const auto rate = window.slope_per_s(clock.now_ns(), protocol.settle.window_s, settle_from);
    if (rate) last_rate = *rate;
    settled = rate && std::abs(*rate) < protocol.settle.max_rate;
    return settled;
  });
  if (why != Interrupt::none) return why;
  rec.settled_t_ns = clock.now_ns();
  if (!settled) {
    emit_event("step",
               fmt::format("step {}: not settled after {} s (rate {:.4g} {}/s, limit {}); recording anyway",
                           step.index + 1, protocol.settle.max_wait_s, last_rate, steps->settle_unit(),
                           protocol.settle.max_rate),
               step.index);
  }
  return Interrupt::none;
}

Interrupt Engine::Impl::hold_phase() {
  if (!(protocol.hold_s > 0)) return Interrupt::none;
  set_state(EngineState::holding, "");
  return wait_until(protocol.hold_s, nullptr);
}

Interrupt Engine::Impl::record_phase(db::StepRecord& rec, WindowObservation& seen) {
  set_state(EngineState::recording, "");
  const std::uint64_t faults_before = instrument_faults;
  recorder.open_window();
  rec.recorded_from_t_ns = clock.now_ns();
  const Interrupt why = wait_until(protocol.record_s, nullptr);
  seen.stats = recorder.close_window();
  seen.faults = instrument_faults - faults_before;
  rec.recorded_to_t_ns = clock.now_ns();
  return why;
}

std::string Engine::Impl::window_problem(const ProtocolStep& step, const WindowObservation& seen) const {
  WindowRequirements need;
  need.record_s = protocol.record_s;
  const std::array<double, kSlots> rate{protocol.rates.tester_Hz, protocol.rates.tester_Hz,
                                        protocol.rates.power_Hz, protocol.rates.pressure_Hz};
  for (int s = 0; s < kSlots; ++s) need.rate_Hz[s] = recorder.channel(s) != 0 ? rate[s] : 0.0;
  // The pressure of a pin protocol is recorded when the lab has a vacuum controller, but no
  // step depends on it: its readings never void a window.
  if (protocol.kind != StepKind::vacuum) need.rate_Hz[kPressure] = 0.0;
  need.min_sample_fraction = protocol.min_sample_fraction;
  need.target_displacement_mm = steps->target_displacement_mm(step);
  need.position_tolerance_mm = protocol.position_tolerance_mm;
  need.baseline_W = baseline_W;
  return window_problems(need, seen);
}

void Engine::Impl::store_step(const ProtocolStep& step, db::StepRecord& rec, const WindowObservation& seen,
                              bool settled) {
  const auto& stats = seen.stats;
  for (int s = 0; s < kSlots; ++s) {
    if (recorder.channel(s) != 0)
      rec.channels.push_back({recorder.channel(s), stats[s].mean(), stats[s].std(), stats[s].n()});
  }
  rec.measured_transmission = stats[kPower].mean() / baseline_W;
  rec.completed = true;
  db.add_step(rec);

  StepResult r;
  r.index = step.index;
  r.step_count = static_cast<int>(protocol.steps.size());
  r.displacement_mm = step.displacement_mm;
  r.nominal_strain = step.nominal_strain;
  r.pressure_kPa = step.pressure_kPa;
  r.measured_displacement_mm = stats[kDisplacement].mean();
  r.load_N = stats[kLoad].mean();
  r.load_std_N = stats[kLoad].std();
  r.power_W = stats[kPower].mean();
  r.power_std_W = stats[kPower].std();
  r.measured_pressure_kPa = stats[kPressure].mean();
  r.measured_T = rec.measured_transmission;
  r.samples = stats[kPower].n();
  r.settled = settled;
  emit_event("step",
             fmt::format("step {}/{} recorded: T = {:.5f} ({} power readings), load {:.4f} N", step.index + 1,
                         r.step_count, r.measured_T, r.samples, r.load_N),
             step.index);
  notify([&](EngineObserver& o) { o.on_step_recorded(r); });
  steps->recorded(r);
}

void Engine::Impl::run_sequence() {
  EngineState final_state = EngineState::completed;
  std::string why = fmt::format("all {} steps recorded", protocol.steps.size());
  try {
    if (inst.tester) load_interlock_armed = true;
    std::size_t i = static_cast<std::size_t>(first_step);
    while (i < protocol.steps.size()) {
      current_step = static_cast<int>(i);
      const Interrupt intr = run_step(protocol.steps[i]);
      if (intr == Interrupt::none) {
        ++i;
        continue;
      }
      if (intr == Interrupt::pause) {
        const auto [reason, for_fault] = control.take_pause();
        seal_watch = false;
        if (inst.tester && !tester_lost) {
          // "paused" means the pin has stopped: wait (bounded) until its poller has sent the stop.
          const std::uint64_t stop_cmd = send_tester("stop", [this] { inst.tester->stop(); });
          wait_command(tester_cmds, stop_cmd, 2.0);
        }
        if (for_fault && opt.unattended) {
          // Nobody can resume a pause here: end the run interrupted (resumable) instead.
          final_state = EngineState::interrupted;
          why = reason +
                fmt::format("; step {} and later are not recorded (resume the run to redo them)", i + 1);
          break;
        }
        set_state(EngineState::paused, reason + fmt::format("; step {} will be redone", i + 1));
        if (control.wait_for_resume()) {
          emit_event("operator", fmt::format("resumed; redoing step {}", i + 1), static_cast<int>(i));
          continue;
        }
      }
      std::tie(final_state, why) = control.stop_reason();
      break;
    }
  } catch (const db::DatabaseError& e) {
    // The storage failed under the sequencer (a step row that could not be written: a full
    // disk, a file-size limit): as for a failed sample commit, the run ends interrupted and
    // resumable, and what was committed stays.
    final_state = EngineState::interrupted;
    why = fmt::format("storage: {}", e.what());
    logger("acquisition")->error("run {}: {}", run_id, why);
  } catch (const std::exception& e) {
    final_state = EngineState::failed;
    why = e.what();
    logger("acquisition")->error("run {}: {}", run_id, e.what());
  }
  finish(final_state, why);
}

void Engine::Impl::finish(EngineState final_state, std::string why) {
  if (final_state == EngineState::aborted) emit_event("operator", "abort: " + why, current_step);
  try {
    set_state(EngineState::retracting, why);
    if (inst.tester && tester_lost) {
      emit_event("fault", "the mechanical tester is unreachable: the pin could not be retracted",
                 current_step);
    } else if (inst.tester) {
      load_interlock_armed = false;  // backing off lowers the load; do not stop the retraction
      const bool retract = (final_state != EngineState::interrupted || protocol.interlocks.retract_on_trip) &&
                           !control.stopping_now();
      const std::uint64_t stop_cmd = send_tester("stop", [this] { inst.tester->stop(); });
      if (tester_limit_latched && retract) {
        // The tester stopped itself at its limit and refuses moves until cleared; backing off
        // only lowers the load.
        send_tester("clear the limit fault to retract", [this] { inst.tester->clear_fault(); });
      }
      if (retract) {
        Interrupt ignored;
        std::string problem;
        if (move_and_wait(0.0, protocol.retract_speed_mm_per_s, false, ignored, problem) !=
            MoveResult::arrived) {
          if (control.stopping_now()) {
            wait_command(tester_cmds, send_tester("stop", [this] { inst.tester->stop(); }), 2.0);
            emit_event("operator",
                       fmt::format("stopped at once: the pin is left at {:.4f} mm (the retraction was cut "
                                   "short by a second abort)",
                                   latest[kDisplacement] + protocol.contact_position_mm),
                       current_step);
          } else {
            emit_event("fault",
                       "pin did not reach home after the run; check the tester" +
                           (problem.empty() ? std::string() : ": " + problem),
                       current_step);
          }
        }
      } else if (control.stopping_now()) {
        wait_command(tester_cmds, stop_cmd, 2.0);
        emit_event("operator",
                   fmt::format("stopped at once: the pin is left at {:.4f} mm (not retracted)",
                               latest[kDisplacement] + protocol.contact_position_mm),
                   current_step);
      }
    }
    if (inst.vacuum && protocol.kind == StepKind::vacuum) {
      seal_watch = false;
      send_vacuum("pump off, vent", [this] {
        inst.vacuum->run_pump(false);
        inst.vacuum->set_vent(true);
      });
      if (!control.stopping_now()) stop_pollers.sleep_for(clock.real(3.0 / protocol.rates.pressure_Hz));
    }
  } catch (const std::exception& e) {
    emit_event("fault", fmt::format("while ending the run: {}", e.what()), current_step);
  }
  stop_pollers.request();
  for (auto& t : pollers) t.join();
  // Everything is in the file and the run has its final status before anyone hears of the
  // final state.
  recorder.stop();
  // A run whose samples did not all reach the file is not complete, even when every step was
  // (a commit that failed after the last step, or a full write queue).
  const db::WriterStats ws = recorder.writer_stats();
  if (const std::uint64_t dropped = recorder.dropped(), lost = dropped + ws.failed_samples;
      lost > 0 && final_state == EngineState::completed) {
    final_state = EngineState::interrupted;
    why = fmt::format(
        "{} sample(s) were not stored ({} refused by the full write queue, {} lost to failed "
        "commits{}): the run's record is incomplete",
        lost, dropped, ws.failed_samples, ws.last_error.empty() ? "" : ": " + ws.last_error);
    emit_event("fault", why, current_step);
  }
  if (final_state == EngineState::interrupted || final_state == EngineState::failed) control.set_error(why);
  const db::RunStatus status = final_state == EngineState::completed ? db::RunStatus::completed
                               : final_state == EngineState::aborted ? db::RunStatus::aborted
                                                                     : db::RunStatus::interrupted;
  try {
    db.set_run_status(run_id, status);
  } catch (const std::exception& e) {
    logger("acquisition")->error("run {}: cannot set status {}: {}", run_id, db::to_string(status), e.what());
  }
  set_state(final_state, why);
  predictions.close();
}

}  // namespace tocd::acquisition
