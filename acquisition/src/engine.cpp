// Run engine lifecycle: start, resume, operator requests, state, observer plumbing.
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/devices/lab.hpp"

namespace tocd::acquisition {

std::string_view to_string(EngineState s) noexcept {
  switch (s) {
    case EngineState::idle:
      return "idle";
    case EngineState::starting:
      return "starting";
    case EngineState::moving:
      return "moving";
    case EngineState::settling:
      return "settling";
    case EngineState::holding:
      return "holding";
    case EngineState::recording:
      return "recording";
    case EngineState::paused:
      return "paused";
    case EngineState::retracting:
      return "retracting";
    case EngineState::completed:
      return "completed";
    case EngineState::aborted:
      return "aborted";
    case EngineState::interrupted:
      return "interrupted";
    case EngineState::failed:
      return "failed";
  }
  return "unknown";
}

bool is_terminal(EngineState s) noexcept {
  return s == EngineState::completed || s == EngineState::aborted || s == EngineState::interrupted ||
         s == EngineState::failed;
}

namespace {

void check_instruments(const Protocol& p, const InstrumentSet& inst) {
  if (!inst.power_meter) {
    throw EngineError("the protocol needs a power meter (T = power / baseline) but the lab has none");
  }
  if (p.kind == StepKind::vacuum && !inst.vacuum) {
    throw EngineError("the protocol has vacuum steps but the lab has no vacuum controller");
  }
  if (p.kind != StepKind::vacuum && !inst.tester) {
    throw EngineError("the protocol has pin steps but the lab has no mechanical tester");
  }
}

/// Zeroes the load cell before a pin run, so that no cell offset reaches the recorded loads
/// (and the material fit). Only with the pin clear of the sample: a tare under load would
/// hide real load. Not on resume, where the pin may be in the sample. Returns the note for
/// the run's event log ("" when there is nothing to say).
std::string tare_load_cell(const Protocol& p, const InstrumentSet& inst) {
  constexpr double kClearance_mm = 0.05;
  if (!inst.tester || p.kind != StepKind::displacement || !p.tare_load) return "";
  try {
    const devices::TesterReading before = inst.tester->read();
    if (!(before.position_mm < p.contact_position_mm - kClearance_mm)) {
      return fmt::format(
          "load cell not tared: the pin is at {:.3f} mm, not clear of the contact position {:.3f} mm "
          "(recorded loads include the cell's offset, {:.4g} N now)",
          before.position_mm, p.contact_position_mm, before.load_N);
    }
    inst.tester->tare_load();
    return fmt::format(
        "load cell tared at {:.3f} mm, clear of the contact position {:.3f} mm (it read {:.4g} N)",
        before.position_mm, p.contact_position_mm, before.load_N);
  } catch (const devices::DeviceError& e) {
    // A transient fault here must not cost the run: the pollers retry and report faults.
    return fmt::format("load cell not tared (recorded loads include the cell's offset): {}", e.what());
  }
}

/// Averages the power meter for the protocol's baseline time, before any run exists.
double measure_baseline(devices::PowerMeter& pm, const Protocol& p, const ScaledClock& clock) {
  RunningStats s;
  const double period_s = 1.0 / p.rates.power_Hz;
  const std::int64_t end = clock.now_ns() + static_cast<std::int64_t>(p.baseline.measure_s * 1e9);
  std::int64_t next = clock.now_ns();
  do {
    const auto r = pm.measure();
    if (r.over_range) throw EngineError("baseline measurement: the power meter reads over range");
    s.add(r.power_W);
    next += static_cast<std::int64_t>(period_s * 1e9);
    clock.sleep_until(next);
  } while (clock.now_ns() < end);
  if (!(s.mean() > 0.0)) {
    throw EngineError(fmt::format(
        "measured glass-only baseline power is {:.4g} W over {} readings: it must be > 0 W (T = power / "
        "baseline); check the light source, the sensor and its zero",
        s.mean(), s.n()));
  }
  return s.mean();
}

/// The travel limit written to the tester: the glass under the sample, which no step reaches
/// (steps stay within [0, thickness) of contact).
double travel_limit_mm(const Protocol& p) {
  return p.contact_position_mm + p.sample.thickness_mm;
}

/// Writes the protocol's load limit and the travel limit into the tester's own limit
/// registers, so that the instrument stops itself whatever the engine's poll rate. Throws
/// EngineError when the tester does not take them.
void write_tester_limits(const Protocol& p, devices::MechanicalTester& tester) {
  try {
    tester.set_limits(travel_limit_mm(p), p.interlocks.max_load_N);
  } catch (const std::exception& e) {
    throw EngineError(
        fmt::format("the mechanical tester did not take the limits (travel {} mm, load {} N): {}",
                    travel_limit_mm(p), p.interlocks.max_load_N, e.what()));
  }
}

std::int64_t register_instrument(db::Database& db, const std::string& kind, devices::Identity id) {
  db::InstrumentRecord r;
  r.kind = kind;
  r.model = id.vendor.empty() ? id.model : id.vendor + " " + id.model;
  r.serial = id.serial;
  r.firmware = id.firmware;
  return db.add_instrument(r);
}

}  // namespace

Engine::Engine(db::Database& db, InstrumentSet instruments, EngineOptions options,
               std::shared_ptr<StepPredictor> predictor, EngineObserver* observer)
    : impl_(std::make_unique<Impl>(db, std::move(instruments), std::move(options), std::move(predictor),
                                   observer)) {
  if (!(impl_->opt.clock_factor > 0.0) || !std::isfinite(impl_->opt.clock_factor)) {
    throw EngineError(fmt::format("clock factor must be > 0, got {}", impl_->opt.clock_factor));
  }
  for (auto& v : impl_->latest) v = std::nan("");
}

Engine::~Engine() {
  if (impl_->sequencer.joinable()) {
    if (!is_terminal(state())) abort("engine destroyed while the run was going");
    // Not wait(): it hands a pause back, and abort() has already ended any pause.
    impl_->control.wait_finished();
    impl_->sequencer.join();
  }
}

namespace {

// The power meter settings stored with a run: the sensor head it reports and the wavelength
// the lab config set on open. Settings the lab config leaves alone (averaging, a wavelength
// of 0) stay the meter's own and are not recorded.
std::map<std::string, std::string> power_meter_settings(devices::PowerMeter& meter, const std::string& lab) {
  std::map<std::string, std::string> out{{"power_meter.sensor", meter.sensor_identity()}};
  try {
    const auto cfg = lab.empty() ? devices::LabConfig{} : devices::parse_lab_config(lab, "lab config");
    if (cfg.power_meter && cfg.power_meter->wavelength_nm > 0)
      out["power_meter.wavelength_nm"] = fmt::format("{}", cfg.power_meter->wavelength_nm);
  } catch (const ConfigError&) {  // a lab text the caller did not parse is stored as it is
  }
  return out;
}

}  // namespace

std::int64_t Engine::start(const Protocol& protocol) {
  auto& m = *impl_;
  if (m.control.state() != EngineState::idle) throw EngineError("this engine already ran; make a new one");
  check_instruments(protocol, m.inst);
  m.protocol = protocol;
  m.baseline_W = protocol.baseline.power_W ? *protocol.baseline.power_W
                                           : measure_baseline(*m.inst.power_meter, protocol, m.clock);

  // Identify the instruments before the run exists: a dead link leaves no half-made run.
  std::array<std::int64_t, kSlots> instrument{};
  if (m.inst.tester) {
    instrument[kDisplacement] = instrument[kLoad] =
        register_instrument(m.db, "mechanical_tester", m.inst.tester->identity());
  }
  instrument[kPower] = register_instrument(m.db, "power_meter", m.inst.power_meter->identity());
  if (m.inst.vacuum) instrument[kPressure] = register_instrument(m.db, "vacuum", m.inst.vacuum->identity());
  const std::string tare_note = tare_load_cell(protocol, m.inst);
  if (m.inst.tester) write_tester_limits(protocol, *m.inst.tester);

  db::SampleRecord sample;
  sample.name = protocol.sample.tissue;
  sample.tissue = protocol.sample.tissue;
  sample.thickness_mm = protocol.sample.thickness_mm;
  sample.notes = protocol.sample.notes;
  db::NewRun nr;
  nr.name = m.opt.run_name.empty() ? protocol.name : m.opt.run_name;
  nr.sample_id = m.db.add_sample(sample);
  nr.protocol_text = protocol.source_text;
  nr.lab_config_text = m.opt.lab_config_text;
  nr.software_version = std::string(version());
  nr.operator_name = m.opt.operator_name;
  nr.baseline_power_W = m.baseline_W;
  nr.settings = power_meter_settings(*m.inst.power_meter, m.opt.lab_config_text);
  nr.clock_factor = m.opt.clock_factor;
  const db::RunRecord run = m.db.create_run(nr);
  m.run_id = run.id;
  m.clock = ScaledClock(m.opt.clock_factor, run.monotonic_anchor_ns);
  try {
    const std::array<double, kSlots> rate{protocol.rates.tester_Hz, protocol.rates.tester_Hz,
                                          protocol.rates.power_Hz, protocol.rates.pressure_Hz};
    for (int s = 0; s < kSlots; ++s) {
      if (instrument[s] == 0) continue;
      db::Channel c;
      c.run_id = m.run_id;
      c.name = std::string(kChannelNames[s]);
      c.unit = std::string(kChannelUnits[s]);
      c.instrument_id = instrument[s];
      c.nominal_rate_Hz = rate[s];
      m.recorder.set_channel(s, m.db.add_channel(c).id);
    }
    if (!tare_note.empty()) m.db.add_event({0, m.run_id, m.clock.now_ns(), "tare", tare_note, -1, ""});
    if (protocol.baseline.measure) {
      m.db.add_event({0, m.run_id, m.clock.now_ns(), "baseline",
                      fmt::format("measured glass-only baseline {:.6g} W over {} s", m.baseline_W,
                                  protocol.baseline.measure_s),
                      -1, ""});
    }
  } catch (...) {
    m.db.set_run_status(m.run_id, db::RunStatus::interrupted);
    throw;
  }
  m.first_step = 0;
  m.start_threads();
  return m.run_id;
}

std::int64_t Engine::resume(std::int64_t run_id) {
  auto& m = *impl_;
  if (m.control.state() != EngineState::idle) throw EngineError("this engine already ran; make a new one");
  const db::RunRecord before = m.db.run(run_id);
  if (before.status != db::RunStatus::interrupted && before.status != db::RunStatus::aborted) {
    throw EngineError(fmt::format("run {} is {}: only an interrupted or aborted run can be resumed", run_id,
                                  db::to_string(before.status)));
  }
  m.protocol = parse_protocol(before.protocol_text, fmt::format("run {} protocol", run_id));
  check_instruments(m.protocol, m.inst);
  if (!(before.baseline_power_W > 0.0)) {
    throw EngineError(
        fmt::format("run {} has no glass-only baseline power stored; it cannot be resumed", run_id));
  }
  m.baseline_W = before.baseline_power_W;

  const db::ResumePoint rp = m.db.resume_run(run_id, m.opt.clock_factor);
  try {
    m.run_id = run_id;
    // The new segment's clock starts where its anchor says (after everything recorded), so
    // the run's timestamps keep increasing across the gap and UTC stays real time.
    m.clock = ScaledClock(m.opt.clock_factor, rp.gap_to_t_ns);
    m.first_step = rp.first_incomplete_step;
    if (m.inst.tester) {
      write_tester_limits(m.protocol, *m.inst.tester);
      // A limit the tester latched when the run stopped would refuse every move: the operator
      // resuming the run clears it, and the run's log says so.
      if (m.inst.tester->read().status.limit) {
        m.inst.tester->clear_fault();
        m.db.add_event({0, run_id, m.clock.now_ns(), "operator",
                        "resume: cleared the limit the mechanical tester had latched", m.first_step, ""});
      }
    }
    const db::Reader reader(m.db.path());
    const std::array<bool, kSlots> present{bool(m.inst.tester), bool(m.inst.tester), true,
                                           bool(m.inst.vacuum)};
    for (int s = 0; s < kSlots; ++s) {
      if (!present[s]) continue;
      if (auto c = reader.channel(run_id, std::string(kChannelNames[s]))) {
        m.recorder.set_channel(s, c->id);
      } else {
        db::Channel c2;
        c2.run_id = run_id;
        c2.name = std::string(kChannelNames[s]);
        c2.unit = std::string(kChannelUnits[s]);
        m.recorder.set_channel(s, m.db.add_channel(c2).id);
      }
    }
  } catch (...) {
    m.db.set_run_status(run_id, db::RunStatus::interrupted);
    throw;
  }
  m.notify([&](EngineObserver& o) { o.on_event(rp.gap_event); });
  m.start_threads();
  return run_id;
}

namespace {

/// Runs a thread's body; whatever it throws becomes a logged error and a trip of the run,
/// never std::terminate.
void guarded(Engine::Impl& m, const char* what, const std::function<void()>& body) {
  try {
    body();
  } catch (const std::exception& e) {
    logger("acquisition")->error("run {}: {} failed: {}", m.run_id, what, e.what());
    m.trip(fmt::format("{} failed: {}", what, e.what()));
  } catch (...) {
    logger("acquisition")->error("run {}: {} failed", m.run_id, what);
    m.trip(fmt::format("{} failed with an unknown error", what));
  }
}

}  // namespace

void Engine::Impl::start_threads() {
  db::WriterOptions wo = opt.writer;
  // A commit that fails loses samples: that is a fault of the run, which ends interrupted
  // (what was committed stays; the run can be resumed once the storage is fixed).
  wo.on_failure = [this, user = opt.writer.on_failure](const db::WriterFailure& f) {
    storage_failed = true;
    trip(fmt::format("storage: a database commit failed, {} sample(s) lost ({} so far): {}", f.samples,
                     f.samples_total, f.error));
    if (user) user(f);
  };
  recorder.start(db, wo);
  steps = protocol.kind == StepKind::vacuum ? make_vacuum_steps(*this) : make_pin_steps(*this);
  load_window.set_keep(2.0 * protocol.settle.window_s + 1.0);
  pressure_window.set_keep(2.0 * protocol.settle.window_s + 1.0);
  segment_start_ns = clock.now_ns();
  current_step = first_step;
  set_state(EngineState::starting,
            first_step < static_cast<int>(protocol.steps.size())
                ? fmt::format("run {} from step {} of {}", run_id, first_step + 1, protocol.steps.size())
                : fmt::format("run {}: all {} steps are already recorded", run_id, protocol.steps.size()));
  if (inst.tester)
    pollers.emplace_back([this] { guarded(*this, "tester poller", [this] { run_tester_poller(); }); });
  pollers.emplace_back([this] { guarded(*this, "power meter poller", [this] { run_power_poller(); }); });
  if (inst.vacuum)
    pollers.emplace_back([this] { guarded(*this, "vacuum poller", [this] { run_vacuum_poller(); }); });
  predictions.start(run_id, [this] {
    // The run's predictions belong to it: its end is when the last of them landed (or was
    // given up), so every time stored with the run lies between its start and its end.
    try {
      db.mark_run_ended(run_id);
    } catch (const std::exception& e) {
      logger("acquisition")->error("run {}: cannot store its end: {}", run_id, e.what());
    }
    control.mark_finished();
  });
  sequencer = std::thread([this] { run_sequence(); });
}

void Engine::Impl::set_state(EngineState s, const std::string& why) {
  if (!control.set_state(s, current_step)) return;
  emit_event("state", fmt::format("{}{}{}", to_string(s), why.empty() ? "" : ": ", why), current_step);
  notify([&](EngineObserver& o) { o.on_state(s, why); });
}

void Engine::Impl::emit_event(const std::string& kind, const std::string& message, int step,
                              const std::string& data_json) {
  db::EventRecord e{0, run_id, clock.now_ns(), kind, message, step, data_json};
  logger("acquisition")->info("run {}: {}: {}", run_id, kind, message);
  if (storage_failed || !recorder.enqueue_event(e)) {
    try {
      db.add_event(e);
    } catch (const std::exception& ex) {  // storage trouble is reported by the writer; never throw here
      logger("acquisition")->error("run {}: event not stored ({}): {}: {}", run_id, ex.what(), kind, message);
    }
  }
  notify([&](EngineObserver& o) { o.on_event(e); });
}

void Engine::Impl::observer_failed(const char* what) noexcept {
  try {
    logger("acquisition")->error("run {}: an observer callback threw: {}", run_id, what);
  } catch (...) {  // logging itself failed: nothing more to do
  }
}

Progress Engine::Impl::make_progress() const {
  Progress p;
  const RunControl::Position at = control.position();
  p.state = at.state;
  p.step_index = at.step;
  p.step_count = static_cast<int>(protocol.steps.size());
  p.elapsed_s = static_cast<double>(clock.now_ns() - segment_start_ns) * 1e-9;
  // Nominal time of the steps left, scaled by how the finished ones compared to nominal.
  const int n = p.step_count;
  const int done = std::max(0, p.step_index - first_step);
  const double per_step = n > 0 ? protocol.nominal_duration_s() / n : 0.0;
  const double observed = done > 0 ? p.elapsed_s / done : per_step;
  p.eta_s = std::max(0.0, (n - p.step_index) * std::max(per_step, observed) - (done > 0 ? 0.0 : p.elapsed_s));
  p.displacement_mm = latest[kDisplacement];
  p.load_N = latest[kLoad];
  p.power_W = latest[kPower];
  p.pressure_kPa = latest[kPressure];
  p.transmission = p.power_W / baseline_W;
  return p;
}

void Engine::pause() {
  impl_->control.pause_by_operator();
}

void Engine::resume() {
  impl_->control.request_resume();
}

void Engine::abort(const std::string& reason) {
  impl_->control.request_abort(reason);
  // The operator wants the run to end now: predictions still running (also after the last
  // step, when nothing else keeps the run) stop too.
  impl_->predictions.cancel("run aborted: " + reason);
}

void Engine::stop_now(const std::string& reason) {
  impl_->control.stop_now(reason);
  impl_->predictions.cancel("run stopped: " + reason);
}

EngineState Engine::wait() {
  return impl_->control.wait_finished_or_paused();
}

bool Engine::wait_for(std::chrono::milliseconds timeout) {
  return impl_->control.wait_finished_for(timeout);
}

EngineState Engine::state() const {
  return impl_->control.state();
}

std::int64_t Engine::run_id() const {
  return impl_->run_id;
}

Progress Engine::progress() const {
  return impl_->make_progress();
}

EngineStats Engine::stats() const {
  EngineStats s;
  s.samples_enqueued = impl_->recorder.enqueued();
  s.samples_dropped = impl_->recorder.dropped();
  s.poll_overruns = impl_->overruns;
  s.writer = impl_->recorder.writer_stats();
  const PredictionQueue::Counts p = impl_->predictions.counts();
  s.predictions_asked = p.asked;
  s.predictions_stored = p.stored;
  s.predictions_failed = p.failed;
  s.predictions_cancelled = p.cancelled;
  return s;
}

std::string Engine::error() const {
  return impl_->control.error();
}

}  // namespace tocd::acquisition
