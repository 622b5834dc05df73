#include "run_opening.hpp"

#include <map>

#include <fmt/format.h>

#include "tocd/core/running_stats.hpp"
#include "tocd/core/version.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/devices/lab.hpp"

namespace tocd::acquisition {

void check_instruments(const Protocol& p, const InstrumentChannels& inst) {
  if (!inst.power) {
    throw EngineError("the protocol needs a power meter (T = power / baseline) but the lab has none");
  }
  if (p.kind == StepKind::vacuum && !inst.vacuum) {
    throw EngineError("the protocol has vacuum steps but the lab has no vacuum controller");
  }
  if (p.kind != StepKind::vacuum && !inst.tester) {
    throw EngineError("the protocol has pin steps but the lab has no mechanical tester");
  }
}

// Only with the pin clear of the sample: a tare under load would hide real load. Not on
// resume, where the pin may be in the sample. The tare keeps any cell offset out of the
// recorded loads (and the material fit).
std::string tare_load_cell(const Protocol& p, TesterChannel* tester) {
  constexpr double kClearance_mm = 0.05;
  if (!tester || p.kind != StepKind::displacement || !p.tare_load) return "";
  try {
    const devices::TesterReading before = tester->driver().read();
    if (!(before.position_mm < p.contact_position_mm - kClearance_mm)) {
      return fmt::format(
          "load cell not tared: the pin is at {:.3f} mm, not clear of the contact position {:.3f} mm "
          "(recorded loads include the cell's offset, {:.4g} N now)",
          before.position_mm, p.contact_position_mm, before.load_N);
    }
    tester->driver().tare_load();
    return fmt::format(
        "load cell tared at {:.3f} mm, clear of the contact position {:.3f} mm (it read {:.4g} N)",
        before.position_mm, p.contact_position_mm, before.load_N);
  } catch (const devices::DeviceError& e) {
    // A transient fault here must not cost the run: the pollers retry and report faults.
    return fmt::format("load cell not tared (recorded loads include the cell's offset): {}", e.what());
  }
}

double measure_baseline(devices::PowerMeter& pm, const Protocol& p, const ScaledClock& clock) {
  RunningStats s;
  const double period_s = 1.0 / p.rates.power_Hz;
  const std::int64_t end = clock.now_ns() + static_cast<std::int64_t>(p.baseline.measure_s * 1e9);
  std::int64_t next = clock.now_ns();
  do {
    const auto r = pm.measure();
    if (r.over_range) throw EngineError("baseline measurement: the power meter reads over range");
    s.add(r.power_W);
    next += static_cast<std::int64_t>(period_s * 1e9);
    clock.sleep_until(next);
  } while (clock.now_ns() < end);
  if (!(s.mean() > 0.0)) {
    throw EngineError(fmt::format(
        "measured glass-only baseline power is {:.4g} W over {} readings: it must be > 0 W (T = power / "
        "baseline); check the light source, the sensor and its zero",
        s.mean(), s.n()));
  }
  return s.mean();
}

namespace {

/// The travel limit written to the tester: the glass under the sample, which no step reaches
/// (steps stay within [0, thickness) of contact).
double travel_limit_mm(const Protocol& p) {
  return p.contact_position_mm + p.sample.thickness_mm;
}

// The power meter settings stored with a run: the sensor head it reports and the wavelength
// the lab config set on open. Settings the lab config leaves alone (averaging, a wavelength
// of 0) stay the meter's own and are not recorded.
std::map<std::string, std::string> power_meter_settings(devices::PowerMeter& meter, const std::string& lab) {
  std::map<std::string, std::string> out{{"power_meter.sensor", meter.sensor_identity()}};
  try {
    const auto cfg = lab.empty() ? devices::LabConfig{} : devices::parse_lab_config(lab, "lab config");
    if (cfg.power_meter && cfg.power_meter->wavelength_nm > 0)
      out["power_meter.wavelength_nm"] = fmt::format("{}", cfg.power_meter->wavelength_nm);
  } catch (const ConfigError&) {  // a lab text the caller did not parse is stored as it is
  }
  return out;
}

/// Calls `f(instrument, k, capability)` for each channel of each present instrument, in order.
template <class F>
void for_each_channel(const InstrumentChannels& instruments, F&& f) {
  const std::vector<InstrumentChannel*> present = instruments.present();
  for (std::size_t i = 0; i < present.size(); ++i) {
    const auto& channels = present[i]->capabilities().channels;
    for (const auto& c : channels) f(i, *present[i], c);
  }
}

}  // namespace

void write_tester_limits(const Protocol& p, devices::MechanicalTester& tester) {
  try {
    tester.set_limits(travel_limit_mm(p), p.interlocks.max_load_N);
  } catch (const std::exception& e) {
    throw EngineError(
        fmt::format("the mechanical tester did not take the limits (travel {} mm, load {} N): {}",
                    travel_limit_mm(p), p.interlocks.max_load_N, e.what()));
  }
}

std::vector<std::int64_t> register_instruments(db::Database& db, const InstrumentChannels& instruments) {
  const auto identify = [&](const devices::InstrumentCapabilities& caps, devices::Identity id) {
    db::InstrumentRecord r;
    r.kind = std::string(caps.kind);
    r.model = id.vendor.empty() ? id.model : id.vendor + " " + id.model;
    r.serial = id.serial;
    r.firmware = id.firmware;
    return db.add_instrument(r);
  };
  std::vector<std::int64_t> ids;
  if (auto* t = instruments.tester.get()) ids.push_back(identify(t->capabilities(), t->driver().identity()));
  if (auto* pm = instruments.power.get())
    ids.push_back(identify(pm->capabilities(), pm->driver().identity()));
  if (auto* v = instruments.vacuum.get()) ids.push_back(identify(v->capabilities(), v->driver().identity()));
  return ids;
}

db::RunRecord create_run(db::Database& db, const Protocol& protocol, const EngineOptions& options,
                         double baseline_W, devices::PowerMeter& meter) {
  db::SampleRecord sample;
  sample.name = protocol.sample.tissue;
  sample.tissue = protocol.sample.tissue;
  sample.thickness_mm = protocol.sample.thickness_mm;
  sample.notes = protocol.sample.notes;
  db::NewRun nr;
  nr.name = options.run_name.empty() ? protocol.name : options.run_name;
  nr.sample_id = db.add_sample(sample);
  nr.protocol_text = protocol.source_text;
  nr.lab_config_text = options.lab_config_text;
  nr.software_version = std::string(version());
  nr.operator_name = options.operator_name;
  nr.baseline_power_W = baseline_W;
  nr.settings = power_meter_settings(meter, options.lab_config_text);
  nr.clock_factor = options.clock_factor;
  return db.create_run(nr);
}

std::vector<std::int64_t> add_channel_rows(db::Database& db, std::int64_t run_id,
                                           const InstrumentChannels& instruments,
                                           const std::vector<std::int64_t>& instrument_ids) {
  std::vector<std::int64_t> ids;
  for_each_channel(instruments, [&](std::size_t i, const InstrumentChannel& instrument,
                                    const devices::ChannelCapability& capability) {
    db::Channel c;
    c.run_id = run_id;
    c.name = std::string(capability.name);
    c.unit = std::string(capability.unit);
    c.instrument_id = instrument_ids.at(i);
    c.nominal_rate_Hz = instrument.rate_Hz();
    ids.push_back(db.add_channel(c).id);
  });
  return ids;
}

std::vector<std::int64_t> find_channel_rows(db::Database& db, std::int64_t run_id,
                                            const InstrumentChannels& instruments) {
  const db::Reader reader(db.path());
  std::vector<std::int64_t> ids;
  for_each_channel(instruments,
                   [&](std::size_t, const InstrumentChannel&, const devices::ChannelCapability& capability) {
                     const std::string name(capability.name);
                     if (auto c = reader.channel(run_id, name)) {
                       ids.push_back(c->id);
                     } else {
                       db::Channel c2;
                       c2.run_id = run_id;
                       c2.name = name;
                       c2.unit = std::string(capability.unit);
                       ids.push_back(db.add_channel(c2).id);
                     }
                   });
  return ids;
}

}  // namespace tocd::acquisition
