#include "instrument_poller.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "tocd/core/clock.hpp"

namespace tocd::acquisition {

namespace {

/// Paces a poller at `rate_Hz` of simulated time. Late polls run back to back (no sample is
/// skipped) unless the poller falls behind by more than 0.5 s of simulated time and 1 s of
/// real time (a stalled driver, not a scheduling hiccup of a fast simulated clock); then it
/// skips ahead and counts an overrun. Its sleeps end at once when the pollers are stopped.
class Pacer {
 public:
  Pacer(const ScaledClock& clock, const StopSignal& stop, double rate_Hz)
      : clock_(clock),
        stop_(stop),
        period_ns_(static_cast<std::int64_t>(1e9 / rate_Hz)),
        max_lag_ns_(static_cast<std::int64_t>(std::max(0.5, clock.factor()) * 1e9)),
        next_(clock.now_ns()) {}
  /// Waits for the next poll; true when it had to skip ahead.
  bool wait() {
    next_ += period_ns_;
    const std::int64_t now = clock_.now_ns();
    if (now - next_ > max_lag_ns_) {
      next_ = now;
      return true;
    }
    const std::int64_t ahead = next_ - now;
    if (ahead > 0) stop_.sleep_for(clock_.real(static_cast<double>(ahead) * 1e-9));
    return false;
  }

 private:
  const ScaledClock& clock_;
  const StopSignal& stop_;
  std::int64_t period_ns_;
  std::int64_t max_lag_ns_;
  std::int64_t next_;
};

/// Tracks an instrument's failures: one event when they start, one when they stop, and a
/// trip when they last longer than the tolerance.
class FaultTracker {
 public:
  FaultTracker(Engine::Impl& m, std::string instrument, bool used)
      : m_(m), instrument_(std::move(instrument)), used_(used) {}

  /// Returns false when the instrument has been failing for too long (the run was tripped,
  /// or for an instrument the protocol does not use, its polling ends); `lost` (optional)
  /// runs before the trip, so whoever handles the trip knows.
  bool failed(const std::exception& e, const std::function<void()>& lost) {
    const std::int64_t now = m_.clock.now_ns();
    if (used_) ++m_.instrument_faults;
    if (count_++ == 0) {
      since_ = now;
      m_.emit_event("fault",
                    fmt::format("{}: {} (the driver's retries did not help){}", instrument_, e.what(),
                                used_ ? "" : "; not used by this protocol, no recording is affected"),
                    current_step());
    }
    if (static_cast<double>(now - since_) * 1e-9 > m_.opt.fault_tolerance_s) {
      if (lost) lost();
      const std::string why =
          fmt::format("{} lost: failing for {:.1f} s ({} failed reads), last error: {}", instrument_,
                      static_cast<double>(now - since_) * 1e-9, count_, e.what());
      if (used_)
        m_.trip(why);
      else
        m_.emit_event("fault", why + "; not used by this protocol: no longer polled", current_step());
      return false;
    }
    return true;
  }
  void succeeded() {
    if (count_ == 0) return;
    m_.emit_event("retry", fmt::format("{}: recovered after {} failed reads", instrument_, count_),
                  current_step());
    count_ = 0;
  }

 private:
  int current_step() { return m_.current_step; }
  Engine::Impl& m_;
  std::string instrument_;
  bool used_;
  std::int64_t count_ = 0;
  std::int64_t since_ = 0;
};

/// Runs the queued commands; a command that throws is an event and a fault, not a crash, and
/// its outcome waits for the sequencer in the queue.
std::uint64_t drain(Engine::Impl& m, CommandQueue& queue, const char* instrument) {
  return queue.drain(
      [&](const std::string& what, const std::string& error) { m.command_failed(instrument, what, error); });
}

/// A poller that fell far behind has skipped readings: that is a fault of the instrument (a
/// stalled driver), and a recording window it falls into is not a measurement.
void overran(Engine::Impl& m, const char* instrument, bool used) {
  ++m.overruns;
  if (used) ++m.instrument_faults;
  m.emit_event("fault",
               fmt::format("{}: readings fell too far behind (a stalled driver); the poller skipped ahead{}",
                           instrument, used ? "" : " (not used by this protocol, no recording is affected)"),
               m.current_step);
}

/// Hands live samples to the observer at most every live_interval_s (real time).
class LiveBatch {
 public:
  explicit LiveBatch(Engine::Impl& m) : m_(m), last_(monotonic_ns()) {}
  std::vector<LiveSample>& buffer() { return buf_; }
  void maybe_flush(bool force = false) {
    if (!m_.observer) {
      buf_.clear();
      return;
    }
    const std::int64_t now = monotonic_ns();
    if (!force && static_cast<double>(now - last_) * 1e-9 < m_.opt.live_interval_s) return;
    if (!buf_.empty()) m_.notify([&](EngineObserver& o) { o.on_samples(buf_); });
    buf_.clear();
    last_ = now;
  }

 private:
  Engine::Impl& m_;
  std::vector<LiveSample> buf_;
  std::int64_t last_;
};

}  // namespace

void run_instrument_poller(Engine::Impl& m, const InstrumentPollerSpec& spec) {
  Pacer pacer(m.clock, m.stop_pollers, spec.rate_Hz);
  FaultTracker faults(m, spec.instrument, spec.used);
  LiveBatch live(m);
  const char* name = spec.instrument.c_str();
  while (!m.stop_pollers.requested()) {
    const std::uint64_t commands_run = spec.commands ? drain(m, *spec.commands, name) : 0;
    try {
      spec.read(commands_run, live.buffer());
      faults.succeeded();
    } catch (const std::exception& e) {
      if (!faults.failed(e, spec.lost)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) overran(m, name, spec.used);
  }
  // Commands queued while the loop ended (a last stop, pump off) still reach the driver.
  if (spec.commands) drain(m, *spec.commands, name);
  live.maybe_flush(true);
}

}  // namespace tocd::acquisition
