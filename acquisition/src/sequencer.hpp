#pragma once

// The sequencer: runs the protocol's steps in explicit phases (move, settle, hold, record;
// what differs between pin and vacuum steps is the StepStrategy's), reacts to pause, abort and
// interlock trips, and ends the run (retract, vent, stop the pollers, final status). It runs on
// its own thread and owns that thread and the run's step strategy; everything else it uses is a
// part of the run handed to it.

#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "fault_policy.hpp"
#include "instrument_channels.hpp"
#include "poller_group.hpp"
#include "prediction_queue.hpp"
#include "recorder.hpp"
#include "run_control.hpp"
#include "run_events.hpp"
#include "run_setup.hpp"
#include "scaled_clock.hpp"
#include "step_sequencer.hpp"
#include "step_strategy.hpp"
#include "window_check.hpp"

namespace tocd::acquisition {

/// The parts of a run the sequencer works with.
struct SequencerParts {
  const RunSetup& setup;
  const EngineOptions& options;
  const ScaledClock& clock;
  db::Database& db;
  RunControl& control;
  RunEvents& events;
  FaultPolicy& faults;
  Recorder& recorder;
  InstrumentChannels& instruments;
  PollerGroup& pollers;
  PredictionQueue& predictions;
  std::function<Progress()> progress;
};

class Sequencer final : public StepSequencer {
 public:
  explicit Sequencer(SequencerParts parts);
  ~Sequencer();
  Sequencer(const Sequencer&) = delete;
  Sequencer& operator=(const Sequencer&) = delete;

  /// Reports the run starting (state `starting`), before any of its threads runs.
  void announce();
  /// Starts the sequencer's thread.
  void start();
  /// Waits for the thread (after the run has finished).
  void join();

  // StepSequencer, for the step strategy.
  Interrupt wait_until(double max_sim_s, const std::function<bool()>& done) override;
  void wait_bounded(double max_sim_s, const std::function<bool()>& done) override;
  Interrupt move_failed(const ProtocolStep& step, const std::string& problem) override;
  void trip(const std::string& reason) override { p_.faults.trip(reason); }

 private:
  struct Ending {
    EngineState state = EngineState::completed;
    std::string why;
  };

  void run();
  /// The steps from the first not recorded on; how the run ends.
  Ending run_steps();
  enum class PauseOutcome { resumed, stopped, ends_run };
  /// A pause the sequencer takes at step `i`: resumed (the step is redone), stopped (an abort
  /// or trip ended the pause), or ends_run (unattended: `unattended` says how the run ends).
  PauseOutcome take_pause(std::size_t i, Ending& unattended);
  /// Waits (real time, bounded) until the tester's poller ran command `id`; false when it did not.
  bool wait_command(TesterChannel& tester, std::uint64_t id, double max_real_s);

  // One step and its phases (sequencer.cpp).
  Interrupt run_step(const ProtocolStep& step);
  Interrupt settle_phase(const ProtocolStep& step, db::StepRecord& rec, bool& settled);
  Interrupt hold_phase(const ProtocolStep& step);
  Interrupt record_phase(const ProtocolStep& step, db::StepRecord& rec, WindowObservation& seen);
  std::string window_problem(const ProtocolStep& step, const WindowObservation& seen) const;
  Interrupt step_incomplete(const ProtocolStep& step, const std::string& problem);
  void store_step(const ProtocolStep& step, db::StepRecord& rec, const WindowObservation& seen, bool settled);
  void set_state(EngineState s, int step, const std::string& why);

  // The end of the run (run_end.cpp).
  void finish(Ending end);
  void end_motion(const Ending& end);
  void retract(bool pin_home);
  void stop_pin_at_once(const char* what);
  void vent();
  /// Samples lost on the way to the file make a completed run interrupted.
  void account_for_lost_samples(Ending& end);
  void store_final_status(Ending& end);

  /// The recorder slot of the run's channel `name`; -1 when it is not recorded.
  int slot_of(std::string_view name) const;

  SequencerParts p_;
  std::unique_ptr<StepStrategy> steps_;
  std::thread thread_;
};

}  // namespace tocd::acquisition
