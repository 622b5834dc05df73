// The sequencer: runs the protocol's steps (move, settle, hold, record), reacts to pause,
// abort and interlock trips, and ends the run.
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine_impl.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"

namespace tocd::acquisition {

namespace {
constexpr double kPositionTolerance_mm = 0.01;
}

Interrupt Engine::Impl::pending_interrupt() const {
  if (tripped) return Interrupt::trip;
  if (abort_requested) return Interrupt::abort;
  if (pause_requested) return Interrupt::pause;
  return Interrupt::none;
}

Interrupt Engine::Impl::wait_until(double max_sim_s, const std::function<bool()>& done) {
  const std::int64_t real_end = monotonic_ns() + clock.real(max_sim_s).count();
  std::int64_t next_progress = 0;
  for (;;) {
    if (done && done()) return Interrupt::none;
    const std::int64_t now = monotonic_ns();
    if (observer && now >= next_progress) {
      observer->on_progress(make_progress());
      next_progress = now + static_cast<std::int64_t>(opt.progress_interval_s * 1e9);
    }
    if (now >= real_end) return Interrupt::none;
    std::unique_lock lock(mu);
    if (const auto i = pending_interrupt(); i != Interrupt::none) return i;
    // Short waits: the done() condition is polled, requests wake us at once.
    const auto slice = std::min<std::int64_t>(real_end - now, done ? 2'000'000 : 20'000'000);
    cv.wait_for(lock, std::chrono::nanoseconds(slice));
    if (const auto i = pending_interrupt(); i != Interrupt::none) return i;
  }
}

void Engine::Impl::send_tester(DriverCommand cmd) {
  {
    std::lock_guard lock(cmd_mu);
    tester_cmds.push_back(std::move(cmd));
  }
  ++tester_commands_sent;  // after the push: a reading tagged with this count follows the command
}

void Engine::Impl::send_vacuum(DriverCommand cmd) {
  std::lock_guard lock(cmd_mu);
  vacuum_cmds.push_back(std::move(cmd));
}

bool Engine::Impl::move_and_wait(double position_mm, double speed_mm_per_s, bool interruptible,
                                 Interrupt& why) {
  const double from = latest[kDisplacement] + protocol.contact_position_mm;
  const double travel =
      std::isfinite(from) ? std::abs(position_mm - from) : protocol.sample.thickness_mm + 10.0;
  send_tester([this, position_mm, speed_mm_per_s] { inst.tester->move_to(position_mm, speed_mm_per_s); });
  const std::uint64_t my_cmd = tester_commands_sent;
  bool arrived = false;
  const auto arrived_fn = [&] {
    const double pos = latest[kDisplacement] + protocol.contact_position_mm;
    arrived = tester_commands_applied >= my_cmd && !tester_moving &&
              (tester_at_target || std::abs(pos - position_mm) <= kPositionTolerance_mm);
    return arrived;
  };
  const double timeout = travel / speed_mm_per_s * 1.5 + opt.move_timeout_margin_s;
  if (interruptible) {
    why = wait_until(timeout, arrived_fn);
  } else {
    why = Interrupt::none;
    const std::int64_t end = monotonic_ns() + clock.real(timeout).count();
    while (!arrived_fn() && monotonic_ns() < end) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return arrived;
}

Interrupt Engine::Impl::run_step(const ProtocolStep& step) {
  const int n = static_cast<int>(protocol.steps.size());
  db::StepRecord rec;
  rec.run_id = run_id;
  rec.index = step.index;
  rec.started_t_ns = clock.now_ns();
  const bool vacuum = protocol.kind == StepKind::vacuum;
  if (vacuum) {
    rec.target_pressure_kPa = step.pressure_kPa;
  } else {
    rec.target_displacement_mm = step.displacement_mm;
    rec.nominal_strain = step.nominal_strain;
  }
  set_state(EngineState::moving,
            vacuum ? fmt::format("step {}/{}: vacuum to {} kPa", step.index + 1, n, step.pressure_kPa)
                   : fmt::format("step {}/{}: pin to {} mm", step.index + 1, n, step.displacement_mm));
  Interrupt why = Interrupt::none;
  if (vacuum) {
    seal_watch = false;
    const double p = step.pressure_kPa;
    send_vacuum([this, p] {
      inst.vacuum->set_vent(false);
      inst.vacuum->set_setpoint_kPa(p);
      inst.vacuum->run_pump(true);
    });
    bool reached = false;
    why = wait_until(protocol.settle.max_wait_s + opt.move_timeout_margin_s, [&] {
      reached = std::abs(latest[kPressure] - p) <= opt.vacuum_reached_kPa;
      return reached;
    });
    if (why != Interrupt::none) return why;
    if (!reached) {
      trip(fmt::format("vacuum did not reach {} kPa (last {:.2f} kPa)", p, latest[kPressure].load()));
      return Interrupt::trip;
    }
    seal_setpoint_kPa = p;
    seal_watch = true;
  } else {
    const double target = protocol.contact_position_mm + step.displacement_mm;
    const bool arrived = move_and_wait(target, protocol.approach_speed_mm_per_s, true, why);
    if (why != Interrupt::none) return why;
    if (!arrived) {
      trip(fmt::format("mechanical tester did not reach position {:.4f} mm in time (at {:.4f} mm)", target,
                       latest[kDisplacement] + protocol.contact_position_mm));
      return Interrupt::trip;
    }
  }

  set_state(EngineState::settling, "");
  const std::int64_t settle_from = clock.now_ns();
  RateWindow& window = vacuum ? pressure_window : load_window;
  bool settled = false;
  double last_rate = std::numeric_limits<double>::quiet_NaN();
  why = wait_until(protocol.settle.max_wait_s, [&] {
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
                           step.index + 1, protocol.settle.max_wait_s, last_rate, vacuum ? "kPa" : "N",
                           protocol.settle.max_rate),
               step.index);
  }

  if (protocol.hold_s > 0) {
    set_state(EngineState::holding, "");
    why = wait_until(protocol.hold_s, nullptr);
    if (why != Interrupt::none) return why;
  }

  set_state(EngineState::recording, "");
  {
    std::lock_guard lock(rec_mu);
    for (auto& s : rec_stats) s.reset();
    recording = true;
  }
  rec.recorded_from_t_ns = clock.now_ns();
  why = wait_until(protocol.record_s, nullptr);
  std::array<RunningStats, kSlots> stats;
  {
    std::lock_guard lock(rec_mu);
    recording = false;
    stats = rec_stats;
  }
  rec.recorded_to_t_ns = clock.now_ns();
  if (why != Interrupt::none) return why;

  for (int s = 0; s < kSlots; ++s) {
    if (channel[s] != 0) rec.channels.push_back({channel[s], stats[s].mean(), stats[s].std(), stats[s].n()});
  }
  rec.measured_transmission = stats[kPower].mean() / baseline_W;
  rec.completed = true;
  db.add_step(rec);

  StepResult r;
  r.index = step.index;
  r.step_count = n;
  r.displacement_mm = step.displacement_mm;
  r.nominal_strain = step.nominal_strain;
  r.pressure_kPa = step.pressure_kPa;
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
                         n, r.measured_T, r.samples, r.load_N),
             step.index);
  if (observer) observer->on_step_recorded(r);
  if (!vacuum && predictor) {
    queue_prediction(
        {run_id, step.index, step.displacement_mm, protocol.sample.thickness_mm, r.load_N, r.measured_T});
  }
  return Interrupt::none;
}

void Engine::Impl::run_sequence() {
  EngineState final_state = EngineState::completed;
  std::string why = fmt::format("all {} steps recorded", protocol.steps.size());
  try {
    if (inst.tester) load_interlock_armed = true;
    std::size_t i = static_cast<std::size_t>(first_step);
    while (i < protocol.steps.size()) {
      {
        std::lock_guard lock(mu);
        current_step = static_cast<int>(i);
      }
      const Interrupt intr = run_step(protocol.steps[i]);
      if (intr == Interrupt::none) {
        ++i;
        continue;
      }
      if (intr == Interrupt::pause) {
        std::string reason;
        {
          std::lock_guard lock(mu);
          reason = pause_reason;
          resume_requested = false;
        }
        seal_watch = false;
        if (inst.tester) send_tester([this] { inst.tester->stop(); });
        set_state(EngineState::paused, reason + fmt::format("; step {} will be redone", i + 1));
        std::unique_lock lock(mu);
        cv.wait(lock, [&] { return resume_requested || abort_requested || tripped; });
        if (resume_requested && !abort_requested && !tripped) {
          pause_requested = false;
          resume_requested = false;
          lock.unlock();
          emit_event("operator", fmt::format("resumed; redoing step {}", i + 1), static_cast<int>(i));
          continue;
        }
        lock.unlock();
      }
      std::lock_guard lock(mu);
      if (tripped) {
        final_state = EngineState::interrupted;
        why = trip_reason;
      } else {
        final_state = EngineState::aborted;
        why = abort_reason;
      }
      break;
    }
  } catch (const std::exception& e) {
    final_state = EngineState::failed;
    why = e.what();
    logger("acquisition")->error("run {}: {}", run_id, e.what());
  }
  finish(final_state, why);
}

void Engine::Impl::finish(EngineState final_state, const std::string& why) {
  if (final_state == EngineState::aborted) emit_event("operator", "abort: " + why, current_step);
  try {
    set_state(EngineState::retracting, why);
    if (inst.tester) {
      load_interlock_armed = false;  // backing off lowers the load; do not stop the retraction
      const bool retract = final_state != EngineState::interrupted || protocol.interlocks.retract_on_trip;
      send_tester([this] { inst.tester->stop(); });
      if (retract) {
        Interrupt ignored;
        if (!move_and_wait(0.0, protocol.retract_speed_mm_per_s, false, ignored)) {
          emit_event("fault", "pin did not reach home after the run; check the tester", current_step);
        }
      }
    }
    if (inst.vacuum && protocol.kind == StepKind::vacuum) {
      seal_watch = false;
      send_vacuum([this] {
        inst.vacuum->run_pump(false);
        inst.vacuum->set_vent(true);
      });
      std::this_thread::sleep_for(clock.real(3.0 / protocol.rates.pressure_Hz));
    }
  } catch (const std::exception& e) {
    emit_event("fault", fmt::format("while ending the run: {}", e.what()), current_step);
  }
  stop_pollers = true;
  for (auto& t : pollers) t.join();
  {
    std::lock_guard lock(mu);
    if (final_state == EngineState::interrupted || final_state == EngineState::failed) error = why;
  }
  set_state(final_state, why);
  writer->stop();
  const db::RunStatus status = final_state == EngineState::completed ? db::RunStatus::completed
                               : final_state == EngineState::aborted ? db::RunStatus::aborted
                                                                     : db::RunStatus::interrupted;
  try {
    db.set_run_status(run_id, status);
  } catch (const std::exception& e) {
    logger("acquisition")->error("run {}: cannot set status {}: {}", run_id, db::to_string(status), e.what());
  }
  {
    std::lock_guard lock(pred_mu);
    pred_stop = true;
  }
  pred_cv.notify_all();
}

}  // namespace tocd::acquisition
