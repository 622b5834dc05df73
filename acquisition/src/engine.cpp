// The engine's public calls: start and resume (which make the run's parts), the operator's
// requests, and what any thread may ask of it.
#include <cmath>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "run_opening.hpp"
#include "tocd/core/enum_names.hpp"

namespace tocd::acquisition {

namespace {
constexpr std::array<EnumName<EngineState>, 12> kEngineStateNames{{{EngineState::idle, "idle"},
                                                                   {EngineState::starting, "starting"},
                                                                   {EngineState::moving, "moving"},
                                                                   {EngineState::settling, "settling"},
                                                                   {EngineState::holding, "holding"},
                                                                   {EngineState::recording, "recording"},
                                                                   {EngineState::paused, "paused"},
                                                                   {EngineState::retracting, "retracting"},
                                                                   {EngineState::completed, "completed"},
                                                                   {EngineState::aborted, "aborted"},
                                                                   {EngineState::interrupted, "interrupted"},
                                                                   {EngineState::failed, "failed"}}};
}  // namespace

std::string_view to_string(EngineState s) noexcept {
  return name_of(kEngineStateNames, s);
}

bool is_terminal(EngineState s) noexcept {
  return s == EngineState::completed || s == EngineState::aborted || s == EngineState::interrupted ||
         s == EngineState::failed;
}

Engine::Engine(db::Database& db, InstrumentSet instruments, EngineOptions options,
               std::shared_ptr<StepPredictor> predictor, EngineObserver* observer)
    : impl_(std::make_unique<Impl>(db, std::move(instruments), std::move(options), std::move(predictor),
                                   observer)) {
  if (!(impl_->options.clock_factor > 0.0) || !std::isfinite(impl_->options.clock_factor)) {
    throw EngineError(fmt::format("clock factor must be > 0, got {}", impl_->options.clock_factor));
  }
}

Engine::~Engine() {
  if (Run* run = impl_->started(); run && run->running()) {
    if (!is_terminal(state())) abort("engine destroyed while the run was going");
    // Not wait(): it hands a pause back, and abort() has already ended any pause.
    impl_->control.wait_finished();
    run->join();
  }
}

void Engine::Impl::refuse_second_run() const {
  if (control.state() != EngineState::idle || run)
    throw EngineError("this engine already ran; make a new one");
}

void Engine::Impl::launch(RunSetup setup, const ScaledClock& clock, const std::vector<std::int64_t>& channels,
                          const db::EventRecord* gap) {
  const std::int64_t run_id = setup.run_id;
  try {
    run = std::make_unique<Run>(RunParts{db, options, observer, predictor, control, instruments},
                                std::move(setup), clock, channels);
    if (gap) run->replay(*gap);
    // Before its threads start: an observer called from them may ask for the run.
    started_run.store(run.get());
    run->start();
  } catch (...) {
    started_run.store(nullptr);
    db.set_run_status(run_id, db::RunStatus::interrupted);
    throw;
  }
}

std::int64_t Engine::start(const Protocol& protocol) {
  auto& m = *impl_;
  m.refuse_second_run();
  check_instruments(protocol, m.instruments);
  RunSetup setup;
  setup.protocol = protocol;
  setup.baseline_W = protocol.baseline.power_W ? *protocol.baseline.power_W
                                               : measure_baseline(m.instruments.power->driver(), protocol,
                                                                  ScaledClock(m.options.clock_factor));

  // Identify the instruments before the run exists: a dead link leaves no half-made run.
  const std::vector<std::int64_t> instrument_ids = register_instruments(m.db, m.instruments);
  const std::string tare_note = tare_load_cell(protocol, m.instruments.tester.get());
  if (m.instruments.tester) write_tester_limits(protocol, m.instruments.tester->driver());

  const db::RunRecord run =
      create_run(m.db, protocol, m.options, setup.baseline_W, m.instruments.power->driver());
  setup.run_id = run.id;
  const ScaledClock clock(m.options.clock_factor, run.monotonic_anchor_ns);
  std::vector<std::int64_t> channels;
  try {
    m.instruments.configure(protocol, setup.baseline_W);
    channels = add_channel_rows(m.db, run.id, m.instruments, instrument_ids);
    if (!tare_note.empty()) m.db.add_event({0, run.id, clock.now_ns(), "tare", tare_note, -1, ""});
    if (protocol.baseline.measure) {
      m.db.add_event({0, run.id, clock.now_ns(), "baseline",
                      fmt::format("measured glass-only baseline {:.6g} W over {} s", setup.baseline_W,
                                  protocol.baseline.measure_s),
                      -1, ""});
    }
  } catch (...) {
    m.db.set_run_status(run.id, db::RunStatus::interrupted);
    throw;
  }
  m.launch(std::move(setup), clock, channels, nullptr);
  return run.id;
}

std::int64_t Engine::resume(std::int64_t run_id) {
  auto& m = *impl_;
  m.refuse_second_run();
  const db::RunRecord before = m.db.run(run_id);
  if (before.status != db::RunStatus::interrupted && before.status != db::RunStatus::aborted) {
    throw EngineError(fmt::format("run {} is {}: only an interrupted or aborted run can be resumed", run_id,
                                  db::to_string(before.status)));
  }
  RunSetup setup;
  setup.protocol = parse_protocol(before.protocol_text, fmt::format("run {} protocol", run_id));
  check_instruments(setup.protocol, m.instruments);
  if (!(before.baseline_power_W > 0.0)) {
    throw EngineError(
        fmt::format("run {} has no glass-only baseline power stored; it cannot be resumed", run_id));
  }
  setup.baseline_W = before.baseline_power_W;
  setup.run_id = run_id;

  const db::ResumePoint rp = m.db.resume_run(run_id, m.options.clock_factor);
  // The new segment's clock starts where its anchor says (after everything recorded), so the
  // run's timestamps keep increasing across the gap and UTC stays real time.
  const ScaledClock clock(m.options.clock_factor, rp.gap_to_t_ns);
  std::vector<std::int64_t> channels;
  try {
    setup.first_step = rp.first_incomplete_step;
    if (TesterChannel* tester = m.instruments.tester.get()) {
      write_tester_limits(setup.protocol, tester->driver());
      // A limit the tester latched when the run stopped would refuse every move: the operator
      // resuming the run clears it, and the run's log says so.
      if (tester->driver().read().status.limit) {
        tester->driver().clear_fault();
        m.db.add_event({0, run_id, clock.now_ns(), "operator",
                        "resume: cleared the limit the mechanical tester had latched", setup.first_step, ""});
      }
    }
    m.instruments.configure(setup.protocol, setup.baseline_W);
    channels = find_channel_rows(m.db, run_id, m.instruments);
  } catch (...) {
    m.db.set_run_status(run_id, db::RunStatus::interrupted);
    throw;
  }
  m.launch(std::move(setup), clock, channels, &rp.gap_event);
  return run_id;
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
  if (Run* run = impl_->started()) run->cancel_predictions("run aborted: " + reason);
}

void Engine::stop_now(const std::string& reason) {
  impl_->control.stop_now(reason);
  if (Run* run = impl_->started()) run->cancel_predictions("run stopped: " + reason);
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
  const Run* run = impl_->started();
  return run ? run->id() : 0;
}

Progress Engine::progress() const {
  if (const Run* run = impl_->started()) return run->progress();
  Progress p;
  p.state = impl_->control.state();
  p.displacement_mm = p.load_N = p.power_W = p.pressure_kPa = p.transmission = std::nan("");
  return p;
}

EngineStats Engine::stats() const {
  const Run* run = impl_->started();
  return run ? run->stats() : EngineStats{};
}

std::string Engine::error() const {
  return impl_->control.error();
}

}  // namespace tocd::acquisition
