// The sequencer's step loop and the phases of one step: move -> settle -> hold -> record; a
// window that is not a measurement sends the step back to its move (bounded), or leaves it
// without a row.
#include "sequencer.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"

namespace tocd::acquisition {

Sequencer::Sequencer(SequencerParts parts) : p_(std::move(parts)) {
  const Protocol& protocol = p_.setup.protocol;
  steps_ = protocol.kind == StepKind::vacuum
               ? make_vacuum_steps(*p_.instruments.vacuum, *this,
                                   protocol.settle.max_wait_s + p_.options.move_timeout_margin_s,
                                   p_.options.vacuum_reached_kPa)
               : make_pin_steps(*p_.instruments.tester, *this, p_.setup, p_.options.move_timeout_margin_s,
                                p_.predictions);
}

Sequencer::~Sequencer() {
  join();
}

void Sequencer::announce() {
  const RunSetup& s = p_.setup;
  const auto n = s.protocol.steps.size();
  set_state(EngineState::starting, s.first_step,
            s.first_step < static_cast<int>(n)
                ? fmt::format("run {} from step {} of {}", s.run_id, s.first_step + 1, n)
                : fmt::format("run {}: all {} steps are already recorded", s.run_id, n));
}

void Sequencer::start() {
  thread_ = std::thread([this] { run(); });
}

void Sequencer::join() {
  if (thread_.joinable()) thread_.join();
}

void Sequencer::set_state(EngineState s, int step, const std::string& why) {
  if (!p_.control.set_state(s, step)) return;
  p_.events.emit("state", fmt::format("{}{}{}", to_string(s), why.empty() ? "" : ": ", why), step);
  p_.events.notify([&](EngineObserver& o) { o.on_state(s, why); });
}

Interrupt Sequencer::wait_until(double max_sim_s, const std::function<bool()>& done) {
  const std::int64_t real_end = monotonic_ns() + p_.clock.real(max_sim_s).count();
  std::int64_t next_progress = 0;
  for (;;) {
    if (done && done()) return Interrupt::none;
    const std::int64_t now = monotonic_ns();
    if (p_.events.has_observer() && now >= next_progress) {
      p_.events.notify([&](EngineObserver& o) { o.on_progress(p_.progress()); });
      next_progress = now + static_cast<std::int64_t>(p_.options.progress_interval_s * 1e9);
    }
    if (now >= real_end) return Interrupt::none;
    // Short waits: the done() condition is polled, requests wake us at once.
    const auto slice = std::min<std::int64_t>(real_end - now, done ? 2'000'000 : 20'000'000);
    if (const auto i = p_.control.wait_for_request(std::chrono::nanoseconds(slice)); i != Interrupt::none)
      return i;
  }
}

void Sequencer::wait_bounded(double max_sim_s, const std::function<bool()>& done) {
  const std::int64_t end = monotonic_ns() + p_.clock.real(max_sim_s).count();
  while (!done() && !p_.control.stopping_now() && monotonic_ns() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

Interrupt Sequencer::move_failed(const ProtocolStep& step, const std::string& problem) {
  const std::string why = fmt::format("step {}: {}", step.index + 1, problem);
  if (p_.setup.protocol.interrupt_on_move_failure) {
    p_.faults.trip(why);
    return Interrupt::trip;
  }
  p_.faults.pause(why);
  return Interrupt::pause;
}

Interrupt Sequencer::step_incomplete(const ProtocolStep& step, const std::string& problem) {
  const std::string why = fmt::format("step {} not recorded after {} recording(s): {}", step.index + 1,
                                      p_.setup.protocol.max_rerecords + 1, problem);
  p_.faults.pause(why);
  return Interrupt::pause;
}

Interrupt Sequencer::run_step(const ProtocolStep& step) {
  const Protocol& protocol = p_.setup.protocol;
  const int n = static_cast<int>(protocol.steps.size());
  for (int attempt = 0;; ++attempt) {
    db::StepRecord rec;
    rec.run_id = p_.setup.run_id;
    rec.index = step.index;
    rec.started_t_ns = p_.clock.now_ns();
    steps_->set_targets(step, rec);
    set_state(EngineState::moving, step.index,
              fmt::format("step {}/{}: {}", step.index + 1, n, steps_->target_text(step)));
    if (const Interrupt why = steps_->approach(step); why != Interrupt::none) return why;
    bool settled = false;
    if (const Interrupt why = settle_phase(step, rec, settled); why != Interrupt::none) return why;
    if (const Interrupt why = hold_phase(step); why != Interrupt::none) return why;
    WindowObservation seen;
    if (const Interrupt why = record_phase(step, rec, seen); why != Interrupt::none) return why;
    // Only a window that holds up is a measurement; otherwise record it again, or leave the
    // step without a row and pause.
    if (const std::string problem = window_problem(step, seen); !problem.empty()) {
      if (attempt >= protocol.max_rerecords) return step_incomplete(step, problem);
      p_.events.emit(
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

Interrupt Sequencer::settle_phase(const ProtocolStep& step, db::StepRecord& rec, bool& settled) {
  const auto& settle = p_.setup.protocol.settle;
  set_state(EngineState::settling, step.index, "");
  const std::int64_t settle_from = p_.clock.now_ns();
  RateWindow& window = steps_->settle_window();
  double last_rate = std::numeric_limits<double>::quiet_NaN();
  const Interrupt why = wait_until(settle.max_wait_s, [&] {
    const auto rate = window.slope_per_s(p_.clock.now_ns(), settle.window_s, settle_from);
    if (rate) last_rate = *rate;
    settled = rate && std::abs(*rate) < settle.max_rate;
    return settled;
  });
  if (why != Interrupt::none) return why;
  rec.settled_t_ns = p_.clock.now_ns();
  if (!settled) {
    p_.events.emit(
        "step",
        fmt::format("step {}: not settled after {} s (rate {:.4g} {}/s, limit {}); recording anyway",
                    step.index + 1, settle.max_wait_s, last_rate, steps_->settle_unit(), settle.max_rate),
        step.index);
  }
  return Interrupt::none;
}

Interrupt Sequencer::hold_phase(const ProtocolStep& step) {
  const double hold_s = p_.setup.protocol.hold_s;
  if (!(hold_s > 0)) return Interrupt::none;
  set_state(EngineState::holding, step.index, "");
  return wait_until(hold_s, nullptr);
}

Interrupt Sequencer::record_phase(const ProtocolStep& step, db::StepRecord& rec, WindowObservation& seen) {
  set_state(EngineState::recording, step.index, "");
  const std::uint64_t faults_before = p_.faults.faults();
  p_.recorder.open_window();
  rec.recorded_from_t_ns = p_.clock.now_ns();
  const Interrupt why = wait_until(p_.setup.protocol.record_s, nullptr);
  seen.stats = p_.recorder.close_window();
  seen.faults = p_.faults.faults() - faults_before;
  rec.recorded_to_t_ns = p_.clock.now_ns();
  return why;
}

int Sequencer::slot_of(std::string_view name) const {
  for (const InstrumentChannel* i : p_.instruments.present()) {
    const auto& channels = i->capabilities().channels;
    for (std::size_t k = 0; k < channels.size(); ++k) {
      if (channels[k].name == name) return i->slot(k);
    }
  }
  return -1;
}

std::string Sequencer::window_problem(const ProtocolStep& step, const WindowObservation& seen) const {
  const Protocol& protocol = p_.setup.protocol;
  WindowRequirements need;
  need.record_s = protocol.record_s;
  need.channels.resize(static_cast<std::size_t>(p_.recorder.slots()));
  // A channel no step depends on (the pressure of a pin protocol, recorded when the lab has a
  // vacuum controller) never voids a window.
  for (const InstrumentChannel* i : p_.instruments.present()) {
    const auto& channels = i->capabilities().channels;
    for (std::size_t k = 0; k < channels.size(); ++k)
      need.channels[static_cast<std::size_t>(i->slot(k))] = {channels[k].name,
                                                             i->used() ? i->rate_Hz() : 0.0};
  }
  need.min_sample_fraction = protocol.min_sample_fraction;
  need.target_displacement_mm = steps_->target_displacement_mm(step);
  need.displacement_slot = slot_of("displacement");
  need.power_slot = slot_of("power");
  need.position_tolerance_mm = protocol.position_tolerance_mm;
  need.baseline_W = p_.setup.baseline_W;
  return window_problems(need, seen);
}

void Sequencer::store_step(const ProtocolStep& step, db::StepRecord& rec, const WindowObservation& seen,
                           bool settled) {
  for (int s = 0; s < p_.recorder.slots(); ++s) {
    const RunningStats st = slot_stats(seen, s);
    rec.channels.push_back({p_.recorder.channel(s), st.mean(), st.std(), st.n()});
  }
  const RunningStats displacement = slot_stats(seen, slot_of("displacement"));
  const RunningStats load = slot_stats(seen, slot_of("load"));
  const RunningStats power = slot_stats(seen, slot_of("power"));
  const RunningStats pressure = slot_stats(seen, slot_of("pressure"));
  rec.measured_transmission = power.mean() / p_.setup.baseline_W;
  rec.completed = true;
  p_.db.add_step(rec);

  StepResult r;
  r.index = step.index;
  r.step_count = static_cast<int>(p_.setup.protocol.steps.size());
  r.displacement_mm = step.displacement_mm;
  r.nominal_strain = step.nominal_strain;
  r.pressure_kPa = step.pressure_kPa;
  r.measured_displacement_mm = displacement.mean();
  r.load_N = load.mean();
  r.load_std_N = load.std();
  r.power_W = power.mean();
  r.power_std_W = power.std();
  r.measured_pressure_kPa = pressure.mean();
  r.measured_T = rec.measured_transmission;
  r.samples = power.n();
  r.settled = settled;
  p_.events.emit("step",
                 fmt::format("step {}/{} recorded: T = {:.5f} ({} power readings), load {:.4f} N",
                             step.index + 1, r.step_count, r.measured_T, r.samples, r.load_N),
                 step.index);
  p_.events.notify([&](EngineObserver& o) { o.on_step_recorded(r); });
  steps_->recorded(r);
}

void Sequencer::run() {
  Ending end;
  try {
    end = run_steps();
  } catch (const db::DatabaseError& e) {
    // The storage failed under the sequencer (a step row that could not be written: a full
    // disk, a file-size limit): as for a failed sample commit, the run ends interrupted and
    // resumable, and what was committed stays.
    end = {EngineState::interrupted, fmt::format("storage: {}", e.what())};
    logger("acquisition")->error("run {}: {}", p_.setup.run_id, end.why);
  } catch (const std::exception& e) {
    end = {EngineState::failed, e.what()};
    logger("acquisition")->error("run {}: {}", p_.setup.run_id, e.what());
  }
  finish(std::move(end));
}

Sequencer::Ending Sequencer::run_steps() {
  const auto& steps = p_.setup.protocol.steps;
  if (p_.instruments.tester) p_.instruments.tester->load_interlock().arm();
  std::size_t i = static_cast<std::size_t>(p_.setup.first_step);
  while (i < steps.size()) {
    const Interrupt intr = run_step(steps[i]);
    if (intr == Interrupt::none) {
      ++i;
      continue;
    }
    if (intr == Interrupt::pause) {
      Ending unattended;
      const PauseOutcome paused = take_pause(i, unattended);
      if (paused == PauseOutcome::resumed) continue;
      if (paused == PauseOutcome::ends_run) return unattended;
    }
    const auto [state, why] = p_.control.stop_reason();
    return {state, why};
  }
  return {EngineState::completed, fmt::format("all {} steps recorded", steps.size())};
}

Sequencer::PauseOutcome Sequencer::take_pause(std::size_t i, Ending& unattended) {
  const auto [reason, for_fault] = p_.control.take_pause();
  if (p_.instruments.vacuum) p_.instruments.vacuum->seal_watch().disarm();
  if (TesterChannel* tester = p_.instruments.tester.get(); tester && !tester->is_lost()) {
    // "paused" means the pin has stopped: wait (bounded) until its poller has sent the stop.
    wait_command(*tester, tester->send_stop(), 2.0);
  }
  if (for_fault && p_.options.unattended) {
    // Nobody can resume a pause here: end the run interrupted (resumable) instead.
    unattended = {
        EngineState::interrupted,
        reason + fmt::format("; step {} and later are not recorded (resume the run to redo them)", i + 1)};
    return PauseOutcome::ends_run;
  }
  set_state(EngineState::paused, static_cast<int>(i),
            reason + fmt::format("; step {} will be redone", i + 1));
  if (!p_.control.wait_for_resume()) return PauseOutcome::stopped;
  p_.events.emit("operator", fmt::format("resumed; redoing step {}", i + 1), static_cast<int>(i));
  return PauseOutcome::resumed;
}

bool Sequencer::wait_command(TesterChannel& tester, std::uint64_t id, double max_real_s) {
  const std::int64_t end = monotonic_ns() + static_cast<std::int64_t>(max_real_s * 1e9);
  while (!tester.queue().outcome(id) && !tester.is_lost() && !p_.control.stopping_now() &&
         monotonic_ns() < end) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return tester.queue().outcome(id).has_value();
}

}  // namespace tocd::acquisition
