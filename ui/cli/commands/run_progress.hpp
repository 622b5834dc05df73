#pragma once

// Terminal view of a running engine (`tocdlab run`, `tocdlab demo`) on stderr: a live status
// line with a bar over the steps, the readings and the ETA, one line per recorded step,
// prediction and notable event. Steps are numbered from 1, as everywhere in tocdlab.

#include <chrono>
#include <mutex>
#include <ostream>

#include "progress.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::cli {

class TerminalProgress : public acquisition::EngineObserver {
 public:
  /// bar: one status line rewritten in place (a terminal); lines: a status line every 5 s;
  /// off: nothing at all (--quiet).
  TerminalProgress(std::ostream& out, ProgressMode mode)
      : out_(out), live_(mode == ProgressMode::bar), off_(mode == ProgressMode::off) {}
  /// On stderr, in stderr_progress_mode().
  TerminalProgress();

  void on_progress(const acquisition::Progress& p) override;
  void on_step_recorded(const acquisition::StepResult& s) override;
  void on_prediction(int step_index, const acquisition::PredictedStep& p) override;
  void on_event(const db::EventRecord& e) override;

 private:
  void line(const std::string& text);  // caller holds mu_
  std::ostream& out_;
  bool live_, off_;
  std::mutex mu_;
  bool status_shown_ = false;
  std::chrono::steady_clock::time_point last_status_{};
};

/// Blocks SIGINT and SIGTERM in the calling thread (and so in every thread it starts later) and
/// turns them into engine.abort() from a watcher thread, so Ctrl-C retracts the pin and keeps
/// the data; a second signal calls engine.stop_now() (the pin stops where it is, no
/// retraction). Restores the signal mask when destroyed.
class AbortOnSignal {
 public:
  explicit AbortOnSignal(std::ostream& err);
  ~AbortOnSignal();
  /// Signals go to `engine` from now on (nullptr: to none). When attach() returns, no call on
  /// the engine attached before is running, so its owner may destroy it.
  void attach(acquisition::Engine* engine);

  /// Attaches an engine for its own lifetime: declared after the engine, it detaches it before
  /// the engine is destroyed, an exception from start() or wait() included.
  class Attached {
   public:
    Attached(AbortOnSignal& signals, acquisition::Engine& engine) : signals_(signals) {
      signals_.attach(&engine);
    }
    ~Attached() { signals_.attach(nullptr); }
    Attached(const Attached&) = delete;
    Attached& operator=(const Attached&) = delete;

   private:
    AbortOnSignal& signals_;
  };

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace tocd::cli
