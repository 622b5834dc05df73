#include "run_control.hpp"

namespace tocd::acquisition {

bool RunControl::set_state(EngineState s, int step) {
  {
    std::lock_guard lock(mu_);
    step_ = step;
    resumed_ = false;  // the sequencer has moved on from its pause (or taken a new one)
    if (state_ == s) return false;
    state_ = s;
  }
  cv_.notify_all();
  return true;
}

EngineState RunControl::state() const {
  std::lock_guard lock(mu_);
  return state_;
}

RunControl::Position RunControl::position() const {
  std::lock_guard lock(mu_);
  return {state_, step_};
}

int RunControl::step() const {
  std::lock_guard lock(mu_);
  return step_;
}

void RunControl::set_error(const std::string& why) {
  std::lock_guard lock(mu_);
  error_ = why;
}

std::string RunControl::error() const {
  std::lock_guard lock(mu_);
  return error_;
}

void RunControl::pause_by_operator() {
  {
    std::lock_guard lock(mu_);
    if (is_terminal(state_) || state_ == EngineState::idle) return;
    pause_requested_ = true;
    pause_for_fault_ = false;
    pause_reason_ = "operator pause";
  }
  cv_.notify_all();
}

bool RunControl::pause_for_fault(const std::string& reason) {
  {
    std::lock_guard lock(mu_);
    if (pause_requested_ || state_ == EngineState::paused) return false;
    pause_requested_ = true;
    pause_for_fault_ = true;
    pause_reason_ = reason;
  }
  cv_.notify_all();
  return true;
}

void RunControl::request_resume() {
  {
    std::lock_guard lock(mu_);
    resume_requested_ = true;
  }
  cv_.notify_all();
}

void RunControl::request_abort(const std::string& reason) {
  {
    std::lock_guard lock(mu_);
    if (abort_requested_) return;
    abort_requested_ = true;
    abort_reason_ = reason;
  }
  cv_.notify_all();
}

void RunControl::stop_now(const std::string& reason) {
  stop_now_ = true;
  request_abort(reason);
  cv_.notify_all();  // also when an abort was already asked for: the sequencer's waits end now
}

bool RunControl::trip(const std::string& reason) {
  bool first = false;
  {
    std::lock_guard lock(mu_);
    if (!tripped_) {
      tripped_ = true;
      trip_reason_ = reason;
      first = true;
    }
  }
  cv_.notify_all();
  return first;
}

Interrupt RunControl::pending_locked() const {
  if (tripped_) return Interrupt::trip;
  if (abort_requested_) return Interrupt::abort;
  if (pause_requested_) return Interrupt::pause;
  return Interrupt::none;
}

Interrupt RunControl::pending() const {
  std::lock_guard lock(mu_);
  return pending_locked();
}

Interrupt RunControl::wait_for_request(std::chrono::nanoseconds slice) {
  std::unique_lock lock(mu_);
  if (const auto i = pending_locked(); i != Interrupt::none) return i;
  cv_.wait_for(lock, slice);
  return pending_locked();
}

RunControl::Pause RunControl::take_pause() {
  std::lock_guard lock(mu_);
  resume_requested_ = false;
  return {pause_reason_, pause_for_fault_};
}

bool RunControl::wait_for_resume() {
  std::unique_lock lock(mu_);
  cv_.wait(lock, [&] { return resume_requested_ || abort_requested_ || tripped_; });
  if (!resume_requested_ || abort_requested_ || tripped_) return false;
  pause_requested_ = pause_for_fault_ = resume_requested_ = false;
  resumed_ = true;
  return true;
}

std::pair<EngineState, std::string> RunControl::stop_reason() const {
  std::lock_guard lock(mu_);
  if (tripped_) return {EngineState::interrupted, trip_reason_};
  return {EngineState::aborted, abort_reason_};
}

void RunControl::mark_finished() {
  {
    std::lock_guard lock(mu_);
    finished_ = true;
  }
  cv_.notify_all();
}

// A paused run goes on only when someone calls resume() or abort(); a caller blocked in
// wait() is often the only one who could, so wait() hands the pause back instead of blocking
// for good (a resume already asked for, or taken but not yet acted on, is not a pause any more).
bool RunControl::waiting_for_operator() const {
  return state_ == EngineState::paused && !resume_requested_ && !resumed_ && !abort_requested_ && !tripped_;
}

EngineState RunControl::wait_finished_or_paused() {
  std::unique_lock lock(mu_);
  if (state_ == EngineState::idle) return state_;
  cv_.wait(lock, [&] { return finished_ || waiting_for_operator(); });
  return state_;
}

bool RunControl::wait_finished_for(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mu_);
  if (state_ == EngineState::idle) return true;
  return cv_.wait_for(lock, timeout, [&] { return finished_; });
}

void RunControl::wait_finished() {
  std::unique_lock lock(mu_);
  cv_.wait(lock, [&] { return finished_; });
}

}  // namespace tocd::acquisition
