// One poller thread per instrument: the only thread that talks to its driver. It executes
// the commands the sequencer queued, reads at the protocol's rate, timestamps and enqueues
// the samples, feeds the settle and recording windows, and checks the interlocks.
#include <cmath>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "tocd/core/clock.hpp"

namespace tocd::acquisition {

namespace {

/// Paces a poller at `rate_Hz` of simulated time. Late polls run back to back (no sample is
/// skipped) unless the poller falls behind by more than 0.5 s of simulated time and 1 s of
/// real time (a stalled driver, not a scheduling hiccup of a fast simulated clock); then it
/// skips ahead and counts an overrun.
class Pacer {
 public:
  Pacer(const ScaledClock& clock, double rate_Hz)
      : clock_(clock),
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
    clock_.sleep_until(next_);
    return false;
  }

 private:
  const ScaledClock& clock_;
  std::int64_t period_ns_;
  std::int64_t max_lag_ns_;
  std::int64_t next_;
};

/// Tracks an instrument's failures: one event when they start, one when they stop, and a
/// trip when they last longer than the tolerance.
class FaultTracker {
 public:
  FaultTracker(Engine::Impl& m, std::string instrument) : m_(m), instrument_(std::move(instrument)) {}

  /// Returns false when the instrument has been failing for too long (the run was tripped).
  bool failed(const std::exception& e) {
    const std::int64_t now = m_.clock.now_ns();
    if (count_++ == 0) {
      since_ = now;
      m_.emit_event("fault", fmt::format("{}: {} (the driver's retries did not help)", instrument_, e.what()),
                    current_step());
    }
    if (static_cast<double>(now - since_) * 1e-9 > m_.opt.fault_tolerance_s) {
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
  int current_step() {
    std::lock_guard lock(m_.mu);
    return m_.current_step;
  }
  Engine::Impl& m_;
  std::string instrument_;
  std::int64_t count_ = 0;
  std::int64_t since_ = 0;
};

/// Runs the queued commands; a command that throws is an event, not a crash.
void drain(Engine::Impl& m, std::deque<DriverCommand>& queue, const char* instrument) {
  for (;;) {
    DriverCommand cmd;
    {
      std::lock_guard lock(m.cmd_mu);
      if (queue.empty()) return;
      cmd = std::move(queue.front());
      queue.pop_front();
    }
    try {
      cmd();
    } catch (const std::exception& e) {
      m.emit_event("fault", fmt::format("{}: command failed: {}", instrument, e.what()));
    }
  }
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
    if (!buf_.empty()) m_.observer->on_samples(buf_);
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
    pause_reason = reason;
  }
  cv.notify_all();
  emit_event("interlock", reason, current_step);
}

void Engine::Impl::run_tester_poller() {
  auto& tester = *inst.tester;
  Pacer pacer(clock, protocol.rates.tester_Hz);
  FaultTracker faults(*this, "mechanical tester");
  LiveBatch live(*this);
  const double max_load = protocol.interlocks.max_load_N;
  bool limit_reported = false;
  while (!stop_pollers) {
    const std::uint64_t sent = tester_commands_sent;
    drain(*this, tester_cmds, "mechanical tester");
    try {
      const devices::TesterReading r = tester.read();
      const std::int64_t t = clock.now_ns();
      faults.succeeded();
      tester_moving = r.status.moving;
      tester_at_target = r.status.at_target;
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
    } catch (const devices::DeviceError& e) {
      if (!faults.failed(e)) {
        try {
          tester.stop();
        } catch (const std::exception&) {  // the link is gone; nothing more to do
        }
        break;
      }
    }
    live.maybe_flush();
    if (pacer.wait()) ++overruns;
  }
  drain(*this, tester_cmds, "mechanical tester");
  live.maybe_flush(true);
}

void Engine::Impl::run_power_poller() {
  auto& pm = *inst.power_meter;
  Pacer pacer(clock, protocol.rates.power_Hz);
  FaultTracker faults(*this, "power meter");
  LiveBatch live(*this);
  bool over_range_reported = false;
  while (!stop_pollers) {
    try {
      const devices::PowerReading r = pm.measure();
      const std::int64_t t = clock.now_ns();
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
    } catch (const devices::DeviceError& e) {
      if (!faults.failed(e)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) ++overruns;
  }
  live.maybe_flush(true);
}

void Engine::Impl::run_vacuum_poller() {
  auto& vac = *inst.vacuum;
  Pacer pacer(clock, protocol.rates.pressure_Hz);
  FaultTracker faults(*this, "vacuum controller");
  LiveBatch live(*this);
  while (!stop_pollers) {
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
    } catch (const devices::DeviceError& e) {
      if (!faults.failed(e)) break;
    }
    live.maybe_flush();
    if (pacer.wait()) ++overruns;
  }
  drain(*this, vacuum_cmds, "vacuum controller");
  live.maybe_flush(true);
}

}  // namespace tocd::acquisition
