#pragma once

// Where a run's events go: into the database in order with its samples (through the recorder's
// writer), straight into the database once the writer cannot take them, to the log, and to the
// observer. It also makes every observer call, so that nothing an observer throws leaves an
// engine thread. Any thread may use it; the one flag it owns (storage failed) is atomic.

#include <atomic>
#include <cstdint>
#include <string>

#include "recorder.hpp"
#include "run_control.hpp"
#include "scaled_clock.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

class RunEvents {
 public:
  RunEvents(db::Database& db, Recorder& recorder, const ScaledClock& clock, const RunControl& control,
            EngineObserver* observer, std::int64_t run_id)
      : db_(db),
        recorder_(recorder),
        clock_(clock),
        control_(control),
        observer_(observer),
        run_id_(run_id) {}

  /// Records an event about `step` (-1: the run as a whole).
  void emit(const std::string& kind, const std::string& message, int step, const std::string& data_json = "");
  /// Records an event about the step under way.
  void emit(const std::string& kind, const std::string& message) { emit(kind, message, control_.step()); }
  /// A commit failed: events go straight to the database from now on (they may still fit).
  void storage_failed() noexcept { storage_failed_ = true; }

  bool has_observer() const noexcept { return observer_ != nullptr; }
  /// Calls the observer (if any) with `call`; whatever the observer throws is logged.
  template <class Call>
  void notify(Call&& call) noexcept {
    if (!observer_) return;
    try {
      call(*observer_);
    } catch (const std::exception& e) {
      observer_failed(e.what());
    } catch (...) {
      observer_failed("unknown error");
    }
  }

 private:
  void observer_failed(const char* what) noexcept;

  db::Database& db_;
  Recorder& recorder_;
  const ScaledClock& clock_;
  const RunControl& control_;
  EngineObserver* observer_;
  const std::int64_t run_id_;
  std::atomic<bool> storage_failed_{false};
};

}  // namespace tocd::acquisition
