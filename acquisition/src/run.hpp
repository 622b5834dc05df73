#pragma once

// A started run: the parts it adds to the engine's instruments and run control, each owning
// its own state: the recorder (writer, channels, recording window), the events, the fault
// policy, the pollers, the sequencer (its thread and step strategy) and the prediction queue.
// Made by Engine::start or Engine::resume once the run exists in the database; the run's
// setup and clock are fixed from then on.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fault_policy.hpp"
#include "instrument_channels.hpp"
#include "poller_group.hpp"
#include "prediction_queue.hpp"
#include "recorder.hpp"
#include "run_control.hpp"
#include "run_events.hpp"
#include "run_setup.hpp"
#include "scaled_clock.hpp"
#include "sequencer.hpp"

namespace tocd::acquisition {

/// What a run is made with besides its setup.
struct RunParts {
  db::Database& db;
  const EngineOptions& options;
  EngineObserver* observer;
  std::shared_ptr<StepPredictor> predictor;
  RunControl& control;
  InstrumentChannels& instruments;
};

class Run {
 public:
  /// `channel_ids`: the run's channel of each recorded channel of the present instruments, in
  /// their order (InstrumentChannels::present(), each instrument's capability table).
  Run(RunParts parts, RunSetup setup, ScaledClock clock, const std::vector<std::int64_t>& channel_ids);
  /// The sequencer's thread is joined first; then the prediction worker.
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  /// Tells the observer of an event already stored (a resumed run's gap).
  void replay(const db::EventRecord& event) {
    events_.notify([&](EngineObserver& o) { o.on_event(event); });
  }
  /// Starts the writer and every thread of the run.
  void start();
  /// Whether start() got as far as the sequencer's thread (which then ends the run).
  bool running() const noexcept { return running_; }
  /// Waits for the sequencer's thread (after the run has finished).
  void join() { sequencer_.join(); }

  std::int64_t id() const noexcept { return setup_.run_id; }
  Progress progress() const;
  EngineStats stats() const;
  /// The predictions not yet stored stop (each gets an event naming `reason`).
  void cancel_predictions(const std::string& reason) { predictions_.cancel(reason); }

 private:
  db::WriterOptions writer_options();

  RunParts parts_;
  const RunSetup setup_;
  const ScaledClock clock_;
  const std::int64_t segment_start_ns_;
  Recorder recorder_;
  RunEvents events_;
  FaultPolicy faults_;
  PollerGroup pollers_;
  // Before the sequencer, which hands it the recorded steps; its worker is joined last.
  PredictionQueue predictions_;
  Sequencer sequencer_;
  std::atomic<bool> running_{false};
};

}  // namespace tocd::acquisition
