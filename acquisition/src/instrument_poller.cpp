#include "instrument_poller.hpp"

#include <algorithm>

#include <fmt/format.h>

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
  FaultTracker(PollerContext& ctx, InstrumentChannel& instrument) : ctx_(ctx), instrument_(instrument) {}

  /// Returns false when the instrument has been failing for too long (the run was tripped,
  /// or for an instrument the protocol does not use, its polling ends); the instrument hears
  /// that it is lost before the trip, so whoever handles the trip knows.
  bool failed(const std::exception& e) {
    const std::int64_t now = ctx_.clock.now_ns();
    const bool used = instrument_.used();
    ctx_.faults.count(used);
    if (count_++ == 0) {
      since_ = now;
      ctx_.events.emit(
          "fault", fmt::format("{}: {} (the driver's retries did not help){}", instrument_.title(), e.what(),
                               used ? "" : "; not used by this protocol, no recording is affected"));
    }
    if (static_cast<double>(now - since_) * 1e-9 > ctx_.faults.tolerance_s()) {
      instrument_.lost();
      const std::string why =
          fmt::format("{} lost: failing for {:.1f} s ({} failed reads), last error: {}", instrument_.title(),
                      static_cast<double>(now - since_) * 1e-9, count_, e.what());
      if (used)
        ctx_.faults.trip(why);
      else
        ctx_.events.emit("fault", why + "; not used by this protocol: no longer polled");
      return false;
    }
    return true;
  }
  void succeeded() {
    if (count_ == 0) return;
    ctx_.events.emit("retry",
                     fmt::format("{}: recovered after {} failed reads", instrument_.title(), count_));
    count_ = 0;
  }

 private:
  PollerContext& ctx_;
  InstrumentChannel& instrument_;
  std::int64_t count_ = 0;
  std::int64_t since_ = 0;
};

/// Runs the queued commands; a command that throws is an event and a fault, not a crash, and
/// its outcome waits for the sequencer in the queue.
std::uint64_t drain(PollerContext& ctx, CommandQueue& queue, const std::string& instrument) {
  return queue.drain([&](const std::string& what, const std::string& error) {
    ctx.faults.command_failed(instrument, what, error);
  });
}

/// A poller that fell far behind has skipped readings: that is a fault of the instrument (a
/// stalled driver), and a recording window it falls into is not a measurement.
void overran(PollerContext& ctx, const InstrumentChannel& instrument) {
  const bool used = instrument.used();
  ctx.faults.overran();
  ctx.faults.count(used);
  ctx.events.emit(
      "fault",
      fmt::format("{}: readings fell too far behind (a stalled driver); the poller skipped ahead{}",
                  instrument.title(), used ? "" : " (not used by this protocol, no recording is affected)"));
}

/// Hands live samples to the observer at most every live_interval_s (real time).
class LiveBatch {
 public:
  explicit LiveBatch(PollerContext& ctx) : ctx_(ctx), last_(monotonic_ns()) {}
  std::vector<LiveSample>& buffer() { return buf_; }
  void maybe_flush(bool force = false) {
    if (!ctx_.events.has_observer()) {
      buf_.clear();
      return;
    }
    const std::int64_t now = monotonic_ns();
    if (!force && static_cast<double>(now - last_) * 1e-9 < ctx_.live_interval_s) return;
    if (!buf_.empty()) ctx_.events.notify([&](EngineObserver& o) { o.on_samples(buf_); });
    buf_.clear();
    last_ = now;
  }

 private:
  PollerContext& ctx_;
  std::vector<LiveSample> buf_;
  std::int64_t last_;
};

}  // namespace

void run_instrument_poller(PollerContext& ctx, InstrumentChannel& instrument) {
  Pacer pacer(ctx.clock, ctx.stop, instrument.rate_Hz());
  FaultTracker faults(ctx, instrument);
  LiveBatch live(ctx);
  const std::string name = instrument.title();
  CommandQueue* commands = instrument.commands();
  while (!ctx.stop.requested()) {
    const std::uint64_t commands_run = commands ? drain(ctx, *commands, name) : 0;
    try {
      instrument.read(ctx, commands_run, live.buffer());
      faults.succeeded();
    } catch (const std::exception& e) {
      if (!faults.failed(e)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) overran(ctx, instrument);
  }
  // Commands queued while the loop ended (a last stop, pump off) still reach the driver.
  if (commands) drain(ctx, *commands, name);
  live.maybe_flush(true);
}

}  // namespace tocd::acquisition
