#pragma once

// The engine's composition root: what it was made with, and its parts. It keeps no state of
// its own: the run control owns the state and the requests, the instrument channels own the
// drivers and everything read from them, and the run (once started) owns its recorder,
// events, fault policy, pollers, sequencer and prediction queue. docs/acquisition.md has the
// table of who owns what.

#include <atomic>
#include <memory>
#include <vector>

#include "instrument_channels.hpp"
#include "run.hpp"
#include "run_control.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

struct Engine::Impl {
  Impl(db::Database& d, InstrumentSet set, EngineOptions o, std::shared_ptr<StepPredictor> p,
       EngineObserver* obs)
      : db(d), options(std::move(o)), predictor(std::move(p)), observer(obs), instruments(std::move(set)) {}

  /// Throws EngineError when this engine already has (or had) a run.
  void refuse_second_run() const;
  /// Makes the run's parts and starts its threads; a run that cannot start is stored
  /// interrupted. `gap`: a resumed run's gap event, for the observer.
  void launch(RunSetup setup, const ScaledClock& clock, const std::vector<std::int64_t>& channels,
              const db::EventRecord* gap);
  /// The run once its threads may be running (any thread reads it); null before.
  Run* started() const noexcept { return started_run.load(); }

  db::Database& db;
  const EngineOptions options;
  const std::shared_ptr<StepPredictor> predictor;
  EngineObserver* const observer;

  RunControl control;
  InstrumentChannels instruments;
  std::unique_ptr<Run> run;  // set once, by start() or resume()
  std::atomic<Run*> started_run{nullptr};
};

}  // namespace tocd::acquisition
