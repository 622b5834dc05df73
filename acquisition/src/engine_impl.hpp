#pragma once

// Private state of the run engine, shared by engine.cpp (lifecycle), pollers.cpp,
// sequencer.cpp and predictions.cpp.

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

#include "rate_window.hpp"
#include "running_stats.hpp"
#include "scaled_clock.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

/// Channel slots of a run (index into the per-channel arrays).
enum Slot : int { kDisplacement = 0, kLoad = 1, kPower = 2, kPressure = 3, kSlots = 4 };
inline constexpr std::array<std::string_view, kSlots> kChannelNames{"displacement", "load", "power",
                                                                    "pressure"};
inline constexpr std::array<std::string_view, kSlots> kChannelUnits{"mm", "N", "W", "kPa"};

/// What interrupted a wait of the sequencer, strongest first.
enum class Interrupt { none, trip, abort, pause };

/// A command the sequencer queues for the thread that owns a driver.
using DriverCommand = std::function<void()>;

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
  std::unique_ptr<db::Writer> writer;
  std::array<std::int64_t, kSlots> channel{};  // 0 = channel not recorded

  // --- state, requests, interlock flags (guarded by mu) ---
  mutable std::mutex mu;
  std::condition_variable cv;
  EngineState state = EngineState::idle;
  std::string error;
  bool pause_requested = false;
  std::string pause_reason;
  bool resume_requested = false;
  bool abort_requested = false;
  std::string abort_reason;
  bool tripped = false;
  std::string trip_reason;
  bool finished = false;  // acquisition over and every prediction landed
  int current_step = 0;
  std::int64_t segment_start_ns = 0;

  // --- latest readings (pollers write, anyone reads) ---
  std::array<std::atomic<double>, kSlots> latest{};
  std::atomic<bool> tester_moving{false}, tester_at_target{false};
  std::atomic<std::uint64_t> tester_commands_applied{0};  // reading taken after this many commands
  std::atomic<std::uint64_t> tester_commands_sent{0};
  std::atomic<bool> load_interlock_armed{true};
  std::atomic<bool> seal_watch{false};  // vacuum setpoint reached in this step: watch for loss
  std::atomic<double> seal_setpoint_kPa{0};
  std::atomic<bool> stop_pollers{false};
  std::atomic<std::uint64_t> enqueued{0}, dropped{0}, overruns{0};

  // --- driver command queues (sequencer -> poller) ---
  std::mutex cmd_mu;
  std::deque<DriverCommand> tester_cmds, vacuum_cmds;

  // --- settle windows and the recording window ---
  RateWindow load_window, pressure_window;
  std::mutex rec_mu;
  bool recording = false;
  std::array<RunningStats, kSlots> rec_stats;

  // --- predictions ---
  std::mutex pred_mu;
  std::condition_variable pred_cv;
  std::deque<RecordedStep> pred_queue;
  bool pred_stop = false;

  std::thread sequencer, prediction_worker;
  std::vector<std::thread> pollers;

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
  void enqueue_sample(int slot, std::int64_t t_ns, double value, std::vector<LiveSample>& live);

  // sequencer.cpp
  void run_sequence();
  Interrupt pending_interrupt() const;  // caller holds mu
  Interrupt wait_until(double max_sim_s, const std::function<bool()>& done);
  Interrupt run_step(const ProtocolStep& step);
  void send_tester(DriverCommand cmd);
  void send_vacuum(DriverCommand cmd);
  bool move_and_wait(double position_mm, double speed_mm_per_s, bool interruptible, Interrupt& why);
  void finish(EngineState final_state, const std::string& why);

  // predictions.cpp
  void run_predictions();
  void queue_prediction(const RecordedStep& step);
};

}  // namespace tocd::acquisition
