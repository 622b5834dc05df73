#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "tocd/acquisition/protocol.hpp"
#include "tocd/acquisition/step_predictor.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition {

/// A run that cannot start or continue: missing instrument, bad baseline, run not resumable.
using EngineError = ErrorOf<struct EngineRun, Error>;

/// Where the engine is. Terminal states: completed, aborted, interrupted, failed.
enum class EngineState {
  idle,         ///< constructed, no run
  starting,     ///< instruments identified, channels made, pollers starting
  moving,       ///< pin (or vacuum) on its way to the step target
  settling,     ///< waiting for the settle criterion
  holding,      ///< hold time after settling
  recording,    ///< recording window of the step
  paused,       ///< operator pause or vacuum seal loss / power over-range; resume() continues
  retracting,   ///< pin going home (end, abort, interlock trip)
  completed,    ///< every step recorded (run status completed)
  aborted,      ///< operator abort (run status aborted; resumable with Engine::resume(run_id))
  interrupted,  ///< interlock trip or lost instrument (run status interrupted; resumable)
  failed        ///< internal error (run status interrupted; see Engine::error())
};

std::string_view to_string(EngineState state) noexcept;
bool is_terminal(EngineState state) noexcept;

/// The instruments a run drives. The engine takes ownership; any may be null when the
/// protocol does not need it (displacement runs: tester + power meter; vacuum runs: vacuum
/// controller + power meter; a tester in a vacuum run, or a vacuum controller in a pin run,
/// is polled and recorded but not driven).
struct InstrumentSet {
  std::unique_ptr<devices::MechanicalTester> tester;
  std::unique_ptr<devices::PowerMeter> power_meter;
  std::unique_ptr<devices::VacuumController> vacuum;
};

/// One live reading for charts. `channel` is one of "displacement" (mm), "load" (N),
/// "power" (W), "pressure" (kPa); it points at static storage.
struct LiveSample {
  std::string_view channel;
  std::int64_t t_ns = 0;
  double value = 0;
};

/// A step as the engine recorded it.
struct StepResult {
  int index = 0;
  int step_count = 0;
  double displacement_mm = 0, nominal_strain = 0, pressure_kPa = 0;  ///< targets
  double measured_displacement_mm = 0;  ///< mean over the recording window (NaN without a tester)
  double load_N = 0, load_std_N = 0;    ///< NaN without a tester
  double power_W = 0, power_std_W = 0;  ///< mean / std over the recording window
  double measured_pressure_kPa = 0;     ///< NaN without a vacuum controller
  double measured_T = 0;                ///< power / baseline power
  std::int64_t samples = 0;             ///< power samples in the window
  bool settled = true;                  ///< false: max_wait_s ran out first
};

/// Where a running protocol is, for progress lines and status bars.
struct Progress {
  EngineState state = EngineState::idle;
  int step_index = 0;  ///< current step (0-based)
  int step_count = 0;
  double elapsed_s = 0;  ///< simulated seconds since the run (segment) started
  double eta_s = 0;      ///< estimate of the simulated seconds left
  double displacement_mm = 0, load_N = 0, power_W = 0, pressure_kPa = 0, transmission = 0;  ///< latest
};

/// Callbacks from a running engine, for a GUI or the terminal.
///
/// Thread contract: every callback is invoked on an engine thread (pollers, sequencer,
/// prediction worker), possibly several at once, never while the engine holds a lock the
/// callback could need: a callback may call Engine::pause/resume/abort/state/progress, but
/// must not block for long (the poller that called it waits) and must not call wait().
/// Whatever a callback throws is logged and dropped (it never stops an engine thread).
/// A Qt GUI forwards them with queued signals. The default implementations do nothing.
class EngineObserver {
 public:
  virtual ~EngineObserver() = default;
  /// Batches of readings, at most every EngineOptions::live_interval_s (real time) per instrument.
  virtual void on_samples(std::span<const LiveSample> samples) { (void)samples; }
  virtual void on_step_recorded(const StepResult& step) { (void)step; }
  virtual void on_prediction(int step_index, const PredictedStep& prediction) {
    (void)step_index;
    (void)prediction;
  }
  /// Every event the run records (state changes, faults, interlocks, operator actions, gaps).
  virtual void on_event(const db::EventRecord& event) { (void)event; }
  virtual void on_state(EngineState state, const std::string& why) {
    (void)state;
    (void)why;
  }
  /// About every EngineOptions::progress_interval_s (real time) while a run is active.
  virtual void on_progress(const Progress& progress) { (void)progress; }
};

struct EngineOptions {
  /// Simulated seconds per real second. 1 for real instruments. > 1 runs a protocol faster
  /// against simulated instruments sharing the same factor (tests, demos): every wait of the
  /// protocol (settle, hold, record, poll periods) shrinks by it, and sample timestamps are
  /// the scaled clock (monotonic at the start of the run, then running `clock_factor` fast).
  double clock_factor = 1.0;
  db::WriterOptions writer;
  std::string operator_name;
  std::string lab_config_text;  ///< stored with the run
  std::string run_name;         ///< default: the protocol's name
  /// A poller gives up (run interrupted) when its instrument keeps failing this long
  /// (simulated seconds); each failure the driver could not retry away is an event.
  double fault_tolerance_s = 2.0;
  double move_timeout_margin_s = 10.0;  ///< added to travel time / speed before a move times out
  double live_interval_s = 0.05;
  double progress_interval_s = 0.2;
  /// Tolerance to call a vacuum setpoint reached (kPa).
  double vacuum_reached_kPa = 1.0;
  /// No operator can resume a pause (a command-line run): a pause for a fault (refused move,
  /// step left incomplete, seal loss, over-range) ends the run interrupted instead, resumable
  /// with resume(run_id). Operator pauses still pause.
  bool unattended = false;
};

/// Counts for tests and status lines.
struct EngineStats {
  std::uint64_t samples_enqueued = 0;  ///< accepted by the writer
  std::uint64_t samples_dropped = 0;   ///< refused by the writer (queue full)
  std::uint64_t poll_overruns = 0;     ///< times a poller fell far behind (stalled driver) and skipped ahead
  db::WriterStats writer;
  /// Predictions of the recorded steps: asked for, stored, failed, and cancelled by an abort
  /// (each one that did not land has a "prediction" event saying why).
  int predictions_asked = 0, predictions_stored = 0, predictions_failed = 0, predictions_cancelled = 0;
};

/// Runs one experiment protocol against the instruments and records it into the database.
///
/// Threads: one poller per instrument at the protocol's rate (the only thread that talks to
/// its driver: commands from the sequencer are queued to it), one sequencer (steps, settle,
/// pause/abort handling), one prediction worker, and the db::Writer's thread. Samples go from
/// the pollers through the writer's bounded queue; step rows, predictions and run status go
/// through db::Database (thread-safe).
///
/// Interlocks are checked by the pollers on every reading: a load above max_load_N (or the
/// tester reporting a limit or fault) stops the motion at once from the poller, records an
/// "interlock" event, retracts the pin (when configured) and ends the run `interrupted`;
/// a vacuum loss in a vacuum run, or a power reading over range, pauses the run. The load
/// limit and a travel limit are also written into the tester's own limit registers at start
/// and on resume, so the instrument stops itself whatever the poll rate.
///
/// A step is recorded only when its move was carried out and ended within the protocol's
/// position tolerance, and its recording window was fault-free with enough readings;
/// otherwise it is recorded again (bounded) or left without a row and the run pauses
/// (docs/acquisition.md).
///
/// All public methods are thread-safe.
class Engine {
 public:
  Engine(db::Database& db, InstrumentSet instruments, EngineOptions options = {},
         std::shared_ptr<StepPredictor> predictor = nullptr, EngineObserver* observer = nullptr);
  /// Aborts a run still going and waits for it.
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Starts a new run of `protocol`; returns its run id at once (the run goes on in the
  /// background). A measured baseline is taken here, before the run exists: a baseline <= 0 W
  /// throws EngineError and writes nothing. Throws EngineError when an instrument the protocol
  /// needs is missing.
  std::int64_t start(const Protocol& protocol);
  /// Continues an interrupted or aborted run from its first step not completed, in the same
  /// run (the database records the gap as an event). Throws EngineError (or db::DatabaseError)
  /// when the run cannot be resumed.
  std::int64_t resume(std::int64_t run_id);

  /// Operator pause: stops the pin where it is; the step under way is redone after resume().
  void pause();
  /// Continues a paused run (operator pause, seal loss, over-range).
  void resume();
  /// Stops motion, retracts the pin, keeps every sample; the run ends `aborted`. Predictions
  /// not yet stored are cancelled (each gets a "prediction" event); called after the last step,
  /// while predictions still run, it only cancels them and the run stays `completed`.
  void abort(const std::string& reason = "operator abort");
  /// Like abort(), but at once: the pin is stopped where it is and not retracted (a second
  /// Ctrl-C, or an abort whose retraction must not be waited for). Also cuts short a
  /// retraction already under way.
  void stop_now(const std::string& reason = "operator stop");

  /// Blocks until the run has ended and every prediction has landed, or until the run is
  /// paused waiting for the operator (nothing but resume() or abort() continues it, and the
  /// caller may be the only one who could call them); returns the state then: a terminal one,
  /// or EngineState::paused. Never blocks on a pause.
  EngineState wait();
  /// Like wait() with a timeout; false when the run is still going.
  bool wait_for(std::chrono::milliseconds timeout);

  EngineState state() const;
  std::int64_t run_id() const;
  Progress progress() const;
  EngineStats stats() const;
  /// Why the run ended interrupted/failed ("" otherwise).
  std::string error() const;

  struct Impl;  ///< defined in acquisition/src only

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::acquisition
