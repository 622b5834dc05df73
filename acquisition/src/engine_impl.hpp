#pragma once

// The run engine's owned parts: the RunControl (state, requests, trips), the Recorder (writer, channels,
// recording window), the PredictionQueue, the command queues, the StepStrategy of the run, and the
// instruments' latest readings (atomics, each written by its one poller). engine.cpp (lifecycle), pollers.cpp
// and instrument_poller.cpp (pollers), sequencer.cpp and step_strategies.cpp (sequencer) use it;
// docs/acquisition.md has the table of who owns what.

#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "channel_slots.hpp"
#include "command_queue.hpp"
#include "prediction_queue.hpp"
#include "rate_window.hpp"
#include "recorder.hpp"
#include "run_control.hpp"
#include "scaled_clock.hpp"
#include "step_strategy.hpp"
#include "stop_signal.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/core/running_stats.hpp"
#include "window_check.hpp"

namespace tocd::acquisition {

/// How a move of the pin ended.
enum class MoveResult { arrived, failed, timed_out, interrupted };

struct Engine::Impl {
  Impl(db::Database& d, InstrumentSet i, EngineOptions o, std::shared_ptr<StepPredictor> p,
       EngineObserver* obs)
      : db(d),
        inst(std::move(i)),
        opt(std::move(o)),
        predictor(std::move(p)),
        observer(obs),
        clock(opt.clock_factor) {}

  db::Database& db;
  InstrumentSet inst;
  EngineOptions opt;
  std::shared_ptr<StepPredictor> predictor;
  EngineObserver* observer;
  ScaledClock clock;

  Protocol protocol;
  std::int64_t run_id = 0;
  double baseline_W = 0;
  int first_step = 0;
  Recorder recorder;

  RunControl control;
  std::atomic<int> current_step{0};  // read by every thread that records an event
  std::int64_t segment_start_ns = 0;

  // --- latest readings (pollers write, anyone reads) ---
  std::array<std::atomic<double>, kSlots> latest{};
  std::atomic<bool> tester_moving{false}, tester_at_target{false};
  std::atomic<std::uint64_t> tester_commands_applied{0};  // reading taken after this many commands
  std::atomic<bool> tester_limit_latched{false};          // the tester reports its limit tripped
  std::atomic<bool> load_interlock_armed{true};
  std::atomic<bool> seal_watch{false};  // vacuum setpoint reached in this step: watch for loss
  std::atomic<double> seal_setpoint_kPa{0};
  StopSignal stop_pollers;
  std::atomic<bool> tester_lost{false};  // its poller gave up: no more commands reach it
  std::atomic<std::uint64_t> overruns{0};
  // Failed reads, failed commands and implausible readings of any instrument: a recording
  // window during which this moved is not a measurement.
  std::atomic<std::uint64_t> instrument_faults{0};
  // A commit failed: events go straight to the database from then on (they may still fit).
  std::atomic<bool> storage_failed{false};

  // --- driver command queues (sequencer -> poller) ---
  CommandQueue tester_cmds, vacuum_cmds;

  // --- settle windows and the recording window ---
  RateWindow load_window, pressure_window;

  std::unique_ptr<StepStrategy> steps;  // pin or vacuum, chosen when the run starts
  std::thread sequencer;
  std::vector<std::thread> pollers;

  /// Calls the observer (if any) with `call`; whatever the observer throws is logged, so that
  /// no exception from it leaves an engine thread.
  template <class Call>
  void notify(Call&& call) noexcept {
    if (!observer) return;
    try {
      call(*observer);
    } catch (const std::exception& e) {
      observer_failed(e.what());
    } catch (...) {
      observer_failed("unknown error");
    }
  }
  void observer_failed(const char* what) noexcept;

  // engine.cpp
  void set_state(EngineState s, const std::string& why);
  void emit_event(const std::string& kind, const std::string& message, int step = -1,
                  const std::string& data_json = "");
  void start_threads();
  Progress make_progress() const;

  // pollers.cpp
  void run_tester_poller();
  void run_power_poller();
  void run_vacuum_poller();
  void trip(const std::string& reason);
  void request_pause(const std::string& reason);
  void command_failed(const char* instrument, const std::string& what, const std::string& error);
  void enqueue_sample(int slot, std::int64_t t_ns, double value, std::vector<LiveSample>& live);

  // sequencer.cpp
  void run_sequence();
  Interrupt wait_until(double max_sim_s, const std::function<bool()>& done);
  Interrupt run_step(const ProtocolStep& step);
  Interrupt settle_phase(const ProtocolStep& step, db::StepRecord& rec, bool& settled);
  Interrupt hold_phase();
  Interrupt record_phase(db::StepRecord& rec, WindowObservation& seen);
  std::string window_problem(const ProtocolStep& step, const WindowObservation& seen) const;
  void store_step(const ProtocolStep& step, db::StepRecord& rec, const WindowObservation& seen, bool settled);
  std::uint64_t send_tester(std::string what, std::function<void()> cmd);
  void send_vacuum(std::string what, std::function<void()> cmd);
  bool wait_command(const CommandQueue& q, std::uint64_t id, double max_real_s);
  MoveResult move_and_wait(double position_mm, double speed_mm_per_s, bool interruptible, Interrupt& why,
                           std::string& problem);
  Interrupt move_failed(const ProtocolStep& step, const std::string& problem);
  Interrupt step_incomplete(const ProtocolStep& step, const std::string& problem);
  void finish(EngineState final_state, std::string why);

  // Last member: destroyed (its worker joined) before anything its callbacks use.
  PredictionQueue predictions{
      db, predictor,
      [this](const std::string& message, int step) { emit_event("prediction", message, step); },
      [this](int step, const PredictedStep& p) {
        notify([&](EngineObserver& o) { o.on_prediction(step, p); });
      }};
};

}  // namespace tocd::acquisition
