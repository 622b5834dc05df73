#pragma once

// Progress of one long job on stderr, the same for every command: a bar with rate and ETA
// redrawn in place when stderr is a terminal, a plain line every few seconds when it is a file
// or a pipe (logs stay readable), nothing with --quiet. Standard output never sees it.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <thread>

#include <spdlog/logger.h>

namespace tocd::cli {

/// How progress reaches the user.
enum class ProgressMode { off, bar, lines };

/// --quiet (set once by main before any command runs) turns every progress display off.
void set_progress_quiet(bool quiet);
bool progress_quiet();

/// off with --quiet; bar when stderr is a terminal; lines otherwise.
ProgressMode stderr_progress_mode();

/// "run N (K steps) recording into DB" on stderr (not with --quiet): where a run that just
/// started goes, for `run` and `demo` alike.
void say_recording_into(std::int64_t run_id, std::size_t steps, const std::string& database);

/// "1:05", "1:02:03"; "-" for an unknown (negative or non-finite) duration.
std::string clock_text(double seconds);

/// One line of a bar: `label [#####.....]  45%  4500/10000 photons  1.2e+04/s  ETA 0:03`.
/// total == 0 means the amount of work is unknown: label, done and elapsed time only.
std::string format_progress(const std::string& label, std::uint64_t done, std::uint64_t total,
                            const std::string& unit, double elapsed_s, int width = 30);

/// A counted job. update() may be called from any thread and as often as convenient: it draws
/// at most every 0.1 s (bar) or every `line_interval` (lines). finish() (or the destructor)
/// draws the last state and ends the line.
class ProgressBar {
 public:
  ProgressBar(std::ostream& out, ProgressMode mode, std::string label, std::uint64_t total, std::string unit,
              std::chrono::milliseconds line_interval = std::chrono::seconds(5));
  /// On stderr, in stderr_progress_mode().
  ProgressBar(std::string label, std::uint64_t total, std::string unit);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::uint64_t done);
  /// A line of its own (a finished row, an event) above the bar; shown in every mode but off.
  void note(const std::string& line);
  void set_total(std::uint64_t total);
  void finish();

 private:
  void draw(std::uint64_t done, bool final);  // caller holds mu_
  std::ostream& out_;
  ProgressMode mode_;
  std::string label_, unit_;
  std::chrono::milliseconds line_interval_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mu_;
  std::uint64_t total_, done_ = 0;
  bool drawn_ = false, finished_ = false;
};

/// A job that cannot count its work (an FE solve, a whole prediction): a thread redraws
/// "label ... elapsed" through a ProgressBar of unknown total until destroyed.
class ElapsedTicker {
 public:
  explicit ElapsedTicker(std::string label);
  ~ElapsedTicker();
  ElapsedTicker(const ElapsedTicker&) = delete;
  ElapsedTicker& operator=(const ElapsedTicker&) = delete;

 private:
  struct State;
  std::unique_ptr<State> state_;
  std::thread thread_;
};

/// A job whose first phase cannot count its work and whose second can (a prediction: FE and
/// meshing, then photons): elapsed time until the first update(), then a bar with rate and
/// ETA over the counted phase alone. update() may be called from any thread.
class PhasedProgress {
 public:
  PhasedProgress(std::string uncounted_label, std::string counted_label, std::string unit);
  PhasedProgress(const PhasedProgress&) = delete;
  PhasedProgress& operator=(const PhasedProgress&) = delete;
  void update(std::uint64_t done, std::uint64_t total);
  void finish();

 private:
  std::mutex mu_;
  std::string counted_label_, unit_;
  std::optional<ElapsedTicker> ticker_;  // until the counted phase starts
  std::optional<ProgressBar> bar_;       // from then on
};

/// Run phase timings at debug level (`--log-level debug`): mark() logs the time since the
/// previous mark; costs a clock read per mark when debug is off.
class PhaseTimer {
 public:
  PhaseTimer(spdlog::logger& log, std::string job)
      : log_(log), job_(std::move(job)), last_(std::chrono::steady_clock::now()) {}
  void mark(const char* phase) const {
    const auto now = std::chrono::steady_clock::now();
    log_.debug("{}: phase '{}' took {:.3f} s", job_, phase,
               std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  spdlog::logger& log_;
  std::string job_;
  mutable std::chrono::steady_clock::time_point last_;
};

}  // namespace tocd::cli
