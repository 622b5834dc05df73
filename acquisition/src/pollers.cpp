// One poller thread per instrument: the only thread that talks to its driver. It executes
// the commands the sequencer queued, reads at the protocol's rate, timestamps and enqueues
// the samples, feeds the settle and recording windows, and checks the interlocks.
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "tocd/core/clock.hpp"

namespace tocd::acquisition {

namespace {

/// A power reading below -this x baseline is not zero noise but a broken reading.
constexpr double kNegativePowerTolerance = 0.01;

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
  /// `lost` (optional) is set before the trip, so whoever handles the trip knows.
  FaultTracker(Engine::Impl& m, std::string instrument, std::atomic<bool>* lost = nullptr)
      : m_(m), instrument_(std::move(instrument)), lost_(lost) {}

  /// Returns false when the instrument has been failing for too long (the run was tripped).
  bool failed(const std::exception& e) {
    const std::int64_t now = m_.clock.now_ns();
    ++m_.instrument_faults;
    if (count_++ == 0) {
      since_ = now;
      m_.emit_event("fault", fmt::format("{}: {} (the driver's retries did not help)", instrument_, e.what()),
                    current_step());
    }
    if (static_cast<double>(now - since_) * 1e-9 > m_.opt.fault_tolerance_s) {
      if (lost_) *lost_ = true;
      m_.trip(fmt::format("{} lost: failing for {:.1f} s ({} failed reads), last error: {}", instrument_,
                          static_cast<double>(now - since_) * 1e-9, count_, e.what()));
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
  std::atomic<bool>* lost_;
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
void overran(Engine::Impl& m, const char* instrument) {
  ++m.overruns;
  ++m.instrument_faults;
  m.emit_event("fault",
               fmt::format("{}: readings fell too far behind (a stalled driver); the poller skipped ahead",
                           instrument),
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

void Engine::Impl::enqueue_sample(int slot, std::int64_t t_ns, double value, std::vector<LiveSample>& live) {
  latest[slot] = value;
  if (channel[slot] != 0) {
    if (writer->enqueue(db::Sample{channel[slot], t_ns, value})) {
      ++enqueued;
    } else {
      ++dropped;
    }
  }
  {
    std::lock_guard lock(rec_mu);
    if (recording) rec_stats[slot].add(value);
  }
  live.push_back({kChannelNames[slot], t_ns, value});
}

void Engine::Impl::command_failed(const char* instrument, const std::string& what, const std::string& error) {
  ++instrument_faults;
  emit_event("fault", fmt::format("{}: command '{}' failed: {}", instrument, what, error), current_step);
}

void Engine::Impl::trip(const std::string& reason) {
  bool first = false;
  {
    std::lock_guard lock(mu);
    if (!tripped) {
      tripped = true;
      trip_reason = reason;
      first = true;
    }
  }
  cv.notify_all();
  if (first) emit_event("interlock", reason, current_step);
}

void Engine::Impl::request_pause(const std::string& reason) {
  {
    std::lock_guard lock(mu);
    if (pause_requested || state == EngineState::paused) return;
    pause_requested = true;
    pause_for_fault = true;
    pause_reason = reason;
  }
  cv.notify_all();
  emit_event("interlock", reason, current_step);
}

void Engine::Impl::run_tester_poller() {
  auto& tester = *inst.tester;
  Pacer pacer(clock, stop_pollers, protocol.rates.tester_Hz);
  FaultTracker faults(*this, "mechanical tester", &tester_lost);
  LiveBatch live(*this);
  const double max_load = protocol.interlocks.max_load_N;
  bool limit_reported = false;
  while (!stop_pollers.requested()) {
    const std::uint64_t sent = drain(*this, tester_cmds, "mechanical tester");
    try {
      const devices::TesterReading r = tester.read();
      const std::int64_t t = clock.now_ns();
      faults.succeeded();
      tester_moving = r.status.moving;
      tester_at_target = r.status.at_target;
      tester_limit_latched = r.status.limit;
      tester_commands_applied = sent;
      const double d = r.position_mm - protocol.contact_position_mm;
      enqueue_sample(kDisplacement, t, d, live.buffer());
      enqueue_sample(kLoad, t, r.load_N, live.buffer());
      load_window.add(t, r.load_N);
      if (load_interlock_armed) {
        // Stop first (this thread owns the driver, so no queue in between), then say why.
        std::string why;
        if (r.load_N > max_load) {
          why = fmt::format("load {:.3f} N above the {:.3f} N limit at displacement {:.4f} mm", r.load_N,
                            max_load, d);
        } else if ((r.status.limit || r.status.fault) && !limit_reported) {
          why = fmt::format("mechanical tester reports {} (fault code {}) at displacement {:.4f} mm",
                            r.status.limit ? "a limit" : "a fault", r.status.fault_code, d);
          limit_reported = true;
        }
        if (!why.empty()) {
          load_interlock_armed = false;
          try {
            tester.stop();
          } catch (const std::exception& e) {
            why += fmt::format("; stop command failed: {}", e.what());
          }
          trip(why);
        }
      }
    } catch (const std::exception& e) {
      if (!faults.failed(e)) {
        try {
          tester.stop();
        } catch (const std::exception&) {  // the link is gone; nothing more to do
        }
        break;
      }
    }
    live.maybe_flush();
    if (pacer.wait()) overran(*this, "mechanical tester");
  }
  drain(*this, tester_cmds, "mechanical tester");
  live.maybe_flush(true);
}

void Engine::Impl::run_power_poller() {
  auto& pm = *inst.power_meter;
  Pacer pacer(clock, stop_pollers, protocol.rates.power_Hz);
  FaultTracker faults(*this, "power meter");
  LiveBatch live(*this);
  bool over_range_reported = false;
  while (!stop_pollers.requested()) {
    try {
      const devices::PowerReading r = pm.measure();
      const std::int64_t t = clock.now_ns();
      // A reading that cannot be light on the sensor is a failed read, not a sample.
      if (!std::isfinite(r.power_W)) {
        throw std::runtime_error(fmt::format("reading {} W is not a number", r.power_W));
      }
      if (r.power_W < -kNegativePowerTolerance * baseline_W) {
        throw std::runtime_error(
            fmt::format("reading {:.4g} W is negative beyond the sensor's zero noise "
                        "(more than {} % of the baseline)",
                        r.power_W, kNegativePowerTolerance * 100.0));
      }
      faults.succeeded();
      enqueue_sample(kPower, t, r.power_W, live.buffer());
      if (r.over_range && !over_range_reported) {
        over_range_reported = true;
        const std::string why = fmt::format("power meter over range ({:.4g} W)", r.power_W);
        if (protocol.interlocks.power_over_range_pauses) {
          request_pause(why);
        } else {
          emit_event("fault", why, current_step);
        }
      } else if (!r.over_range) {
        over_range_reported = false;
      }
    } catch (const std::exception& e) {
      if (!faults.failed(e)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) overran(*this, "power meter");
  }
  live.maybe_flush(true);
}

void Engine::Impl::run_vacuum_poller() {
  auto& vac = *inst.vacuum;
  Pacer pacer(clock, stop_pollers, protocol.rates.pressure_Hz);
  FaultTracker faults(*this, "vacuum controller");
  LiveBatch live(*this);
  while (!stop_pollers.requested()) {
    drain(*this, vacuum_cmds, "vacuum controller");
    try {
      const devices::VacuumReading r = vac.read();
      const std::int64_t t = clock.now_ns();
      faults.succeeded();
      enqueue_sample(kPressure, t, r.pressure_kPa, live.buffer());
      pressure_window.add(t, r.pressure_kPa);
      if (seal_watch && r.pressure_kPa > seal_setpoint_kPa + protocol.interlocks.vacuum_loss_kPa) {
        seal_watch = false;
        request_pause(fmt::format("vacuum seal loss: {:.2f} kPa, setpoint {:.2f} kPa (limit +{:.2f} kPa)",
                                  r.pressure_kPa, seal_setpoint_kPa.load(),
                                  protocol.interlocks.vacuum_loss_kPa));
      }
    } catch (const std::exception& e) {
      if (!faults.failed(e)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) overran(*this, "vacuum controller");
  }
  drain(*this, vacuum_cmds, "vacuum controller");
  live.maybe_flush(true);
}

}  // namespace tocd::acquisition
