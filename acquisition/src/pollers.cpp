// What each instrument's reading means: the tester's, the power meter's and the vacuum
// controller's read steps for the generic poller (instrument_poller.cpp), which timestamp and
// enqueue the samples, feed the settle and recording windows, and check the interlocks.
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "instrument_poller.hpp"
#include "tocd/core/clock.hpp"

namespace tocd::acquisition {

namespace {

/// A power reading below -this x baseline is not zero noise but a broken reading.
constexpr double kNegativePowerTolerance = 0.01;

}  // namespace

void Engine::Impl::enqueue_sample(int slot, std::int64_t t_ns, double value, std::vector<LiveSample>& live) {
  latest[slot] = value;
  recorder.add(slot, t_ns, value);
  live.push_back({kChannelNames[slot], t_ns, value});
}

void Engine::Impl::command_failed(const char* instrument, const std::string& what, const std::string& error) {
  ++instrument_faults;
  emit_event("fault", fmt::format("{}: command '{}' failed: {}", instrument, what, error), current_step);
}

void Engine::Impl::trip(const std::string& reason) {
  if (control.trip(reason)) emit_event("interlock", reason, current_step);
}

void Engine::Impl::request_pause(const std::string& reason) {
  if (control.pause_for_fault(reason)) emit_event("interlock", reason, current_step);
}

void Engine::Impl::run_tester_poller() {
  auto& tester = *inst.tester;
  const double max_load = protocol.interlocks.max_load_N;
  bool limit_reported = false;
  InstrumentPollerSpec spec;
  spec.instrument = "mechanical tester";
  spec.rate_Hz = protocol.rates.tester_Hz;
  spec.commands = &tester_cmds;
  spec.read = [&](std::uint64_t commands_run, std::vector<LiveSample>& live) {
    const devices::TesterReading r = tester.read();
    const std::int64_t t = clock.now_ns();
    tester_moving = r.status.moving;
    tester_at_target = r.status.at_target;
    tester_limit_latched = r.status.limit;
    tester_commands_applied = commands_run;
    const double d = r.position_mm - protocol.contact_position_mm;
    enqueue_sample(kDisplacement, t, d, live);
    enqueue_sample(kLoad, t, r.load_N, live);
    load_window.add(t, r.load_N);
    if (!load_interlock_armed) return;
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
    if (why.empty()) return;
    load_interlock_armed = false;
    try {
      tester.stop();
    } catch (const std::exception& e) {
      why += fmt::format("; stop command failed: {}", e.what());
    }
    trip(why);
  };
  spec.lost = [&] {
    tester_lost = true;  // no more commands reach it: the sequencer stops waiting on them
    try {
      tester.stop();
    } catch (const std::exception&) {  // the link is gone; nothing more to do
    }
  };
  run_instrument_poller(*this, spec);
}

void Engine::Impl::run_power_poller() {
  auto& pm = *inst.power_meter;
  bool over_range_reported = false;
  InstrumentPollerSpec spec;
  spec.instrument = "power meter";
  spec.rate_Hz = protocol.rates.power_Hz;
  spec.read = [&](std::uint64_t, std::vector<LiveSample>& live) {
    const devices::PowerReading r = pm.measure();
    const std::int64_t t = clock.now_ns();
    // Over range first: the driver reports it with a power of +inf (SCPI's 9.9E37). It is no
    // sample and no broken read but a state of the meter, which the protocol's interlock
    // decides about; a window it falls into is no measurement.
    if (r.over_range) {
      ++instrument_faults;
      if (over_range_reported) return;
      over_range_reported = true;
      const std::string why = fmt::format("power meter over range ({:.4g} W)", r.power_W);
      if (protocol.interlocks.power_over_range_pauses) {
        request_pause(why);
      } else {
        emit_event("fault", why, current_step);
      }
      return;
    }
    over_range_reported = false;
    // A reading that cannot be light on the sensor is a failed read, not a sample.
    if (!std::isfinite(r.power_W))
      throw std::runtime_error(fmt::format("reading {} W is not a number", r.power_W));
    if (r.power_W < -kNegativePowerTolerance * baseline_W) {
      throw std::runtime_error(fmt::format(
          "reading {:.4g} W is negative beyond the sensor's zero noise (more than {} % of the baseline)",
          r.power_W, kNegativePowerTolerance * 100.0));
    }
    enqueue_sample(kPower, t, r.power_W, live);
  };
  run_instrument_poller(*this, spec);
}

void Engine::Impl::run_vacuum_poller() {
  auto& vac = *inst.vacuum;
  InstrumentPollerSpec spec;
  spec.instrument = "vacuum controller";
  spec.rate_Hz = protocol.rates.pressure_Hz;
  spec.commands = &vacuum_cmds;
  spec.used = protocol.kind == StepKind::vacuum;
  spec.read = [&](std::uint64_t, std::vector<LiveSample>& live) {
    const devices::VacuumReading r = vac.read();
    const std::int64_t t = clock.now_ns();
    enqueue_sample(kPressure, t, r.pressure_kPa, live);
    pressure_window.add(t, r.pressure_kPa);
    if (seal_watch && r.pressure_kPa > seal_setpoint_kPa + protocol.interlocks.vacuum_loss_kPa) {
      seal_watch = false;
      request_pause(fmt::format("vacuum seal loss: {:.2f} kPa, setpoint {:.2f} kPa (limit +{:.2f} kPa)",
                                r.pressure_kPa, seal_setpoint_kPa.load(),
                                protocol.interlocks.vacuum_loss_kPa));
    }
  };
  run_instrument_poller(*this, spec);
}

}  // namespace tocd::acquisition
