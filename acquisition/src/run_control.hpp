#pragma once

// The run's control state: where the run is (EngineState and the step it is about: the one
// place the current step is kept), what has been asked of it (pause, resume, abort, stop at
// once), whether an interlock tripped it and whether it has finished.
// One mutex guards all of it and every request wakes the waiters at once. The engine's public
// calls (operator requests, wait), the pollers (trips, fault pauses) and the sequencer (its
// waits and state changes) reach it only through these members.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <utility>

#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

/// What interrupted a wait of the sequencer, strongest first.
enum class Interrupt { none, trip, abort, pause };

class RunControl {
 public:
  // --- state ---
  /// Sets the state and the step it is about (0-based); false when the state already was `s`
  /// (nothing to report). The two change together, so that nobody sees a new step in the
  /// previous step's state.
  bool set_state(EngineState s, int step);
  EngineState state() const;
  struct Position {
    EngineState state = EngineState::idle;
    int step = 0;
  };
  Position position() const;
  /// The step under way (0-based): what events of any thread are about.
  int step() const;
  /// Why the run ended interrupted or failed.
  void set_error(const std::string& why);
  std::string error() const;

  // --- requests, from any thread ---
  /// The operator's pause; ignored before the run starts and after it has ended.
  void pause_by_operator();
  /// A fault's pause; false when the run is already paused or pausing (nothing new to report).
  bool pause_for_fault(const std::string& reason);
  void request_resume();
  /// The first abort's reason is kept.
  void request_abort(const std::string& reason);
  /// A second abort: the pin is stopped where it is, without retraction.
  void stop_now(const std::string& reason);
  bool stopping_now() const { return stop_now_; }
  /// An interlock trip; true for the first one (the one to report).
  bool trip(const std::string& reason);

  // --- the sequencer ---
  Interrupt pending() const;
  /// Waits at most `slice` for a request; what is pending then.
  Interrupt wait_for_request(std::chrono::nanoseconds slice);
  struct Pause {
    std::string reason;
    bool for_fault = false;  ///< not the operator's: an unattended run ends instead of pausing
  };
  /// The pause the sequencer is taking; a resume asked for before it is forgotten.
  Pause take_pause();
  /// Blocks until resume, abort or trip; true (the pause cleared) when resumed.
  bool wait_for_resume();
  /// How a run stopped by an abort or a trip ends: interrupted (trip) or aborted, and why.
  std::pair<EngineState, std::string> stop_reason() const;

  // --- the end ---
  /// Acquisition over and every prediction landed.
  void mark_finished();
  /// Blocks until finished or until the run waits in a pause that only a caller can end
  /// (Engine::wait); the state then.
  EngineState wait_finished_or_paused();
  bool wait_finished_for(std::chrono::milliseconds timeout);
  void wait_finished();

 private:
  Interrupt pending_locked() const;
  bool waiting_for_operator() const;  // caller holds mu_

  mutable std::mutex mu_;
  std::condition_variable cv_;
  EngineState state_ = EngineState::idle;
  int step_ = 0;
  std::string error_;
  bool pause_requested_ = false, pause_for_fault_ = false, resume_requested_ = false;
  // The sequencer took the resume and has not yet set its next state: the run is still
  // `paused` on paper but nobody has to resume it again.
  bool resumed_ = false;
  std::string pause_reason_;
  bool abort_requested_ = false;
  std::string abort_reason_;
  std::atomic<bool> stop_now_{false};  // read without the lock by the sequencer's bounded waits
  bool tripped_ = false;
  std::string trip_reason_;
  bool finished_ = false;
};

}  // namespace tocd::acquisition
