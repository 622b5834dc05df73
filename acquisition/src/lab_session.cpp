// The lab session: the one place where instruments, database, predictor and engine are wired.
#include "tocd/acquisition/lab_session.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "demo_protocol_text.hpp"

namespace tocd::acquisition {

namespace {

EngineOptions with_lab_text(EngineOptions e, const devices::LabConfig& lab) {
  if (e.lab_config_text.empty()) e.lab_config_text = devices::to_toml(lab);
  return e;
}

}  // namespace

InstrumentSet to_instrument_set(devices::LabInstruments lab) {
  return InstrumentSet{std::move(lab.tester), std::move(lab.power_meter), std::move(lab.vacuum)};
}

LabSession::LabSession(db::Database& db, InstrumentSet instruments, LabSessionOptions options,
                       EngineObserver* observer)
    : db_(db),
      engine_(std::make_unique<Engine>(db, std::move(instruments), options.engine, options.predictor,
                                       observer)) {}

LabSession::LabSession(db::Database& db, const devices::LabConfig& lab, LabSessionOptions options,
                       EngineObserver* observer)
    : LabSession(db, to_instrument_set(devices::open_lab(lab)),
                 LabSessionOptions{with_lab_text(options.engine, lab), options.predictor}, observer) {}

namespace {

/// The fastest poll rate `protocol` asks of an instrument it uses, and which one.
std::pair<double, const char*> fastest_rate(const Protocol& p) {
  std::pair<double, const char*> out{p.rates.power_Hz, "power meter"};
  if (p.kind != StepKind::vacuum && p.rates.tester_Hz > out.first) out = {p.rates.tester_Hz, "tester"};
  if (p.kind == StepKind::vacuum && p.rates.pressure_Hz > out.first)
    out = {p.rates.pressure_Hz, "vacuum controller"};
  return out;
}

}  // namespace

double max_simulated_clock_factor(const Protocol& protocol) {
  // Two decimals, rounded down: the factor named must itself pass the check.
  return std::floor(100.0 * kMaxSimulatedReadingsPerSecond / fastest_rate(protocol).first) / 100.0;
}

void check_simulated_clock_factor(const Protocol& protocol, double clock_factor) {
  const auto [rate, instrument] = fastest_rate(protocol);
  if (rate * clock_factor <= kMaxSimulatedReadingsPerSecond) return;
  throw ConfigError(
      fmt::format("clock factor {:g}: the protocol reads the {} at {:g} Hz, {:g} readings per real second of "
                  "the simulated "
                  "lab, which keeps up with at most {:g}; use a clock factor of {:g} or less",
                  clock_factor, instrument, rate, rate * clock_factor, kMaxSimulatedReadingsPerSecond,
                  max_simulated_clock_factor(protocol)));
}

std::string_view demo_protocol_text() {
  return kDemoProtocolToml;
}

Protocol demo_protocol() {
  return parse_protocol(std::string(demo_protocol_text()), "protocols/demo.toml");
}

}  // namespace tocd::acquisition
