// The Thorlabs PM100-class SCPI subset over any ScpiLink (docs/instruments/power-meter.md).
#include <cmath>
#include <limits>
#include <thread>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/core/printable.hpp"
#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/devices/usbtmc.hpp"

namespace tocd::devices {
namespace {

std::chrono::milliseconds ms(double seconds) {
  return std::chrono::milliseconds{static_cast<long long>(std::ceil(seconds * 1000.0))};
}

ScpiClientOptions client_options(const std::string& who, const PowerMeterOptions& o) {
  if (!(o.timeout_s > 0.0) || !std::isfinite(o.timeout_s))
    throw ConfigError(fmt::format("{}: timeout_s must be a positive number of seconds", who));
  if (o.retries < 0 || o.retries > 20) throw ConfigError(fmt::format("{}: retries must be 0..20", who));
  if (!(o.negative_tolerance_W >= 0.0 && o.negative_tolerance_W <= 1e-3))
    throw ConfigError(
        fmt::format("{}: negative_tolerance_W must be 0..1e-3 W, got {}", who, o.negative_tolerance_W));
  if (!(o.zero_timeout_s > 0.0) || !(o.zero_poll_s > 0.0))
    throw ConfigError(fmt::format("{}: zero_timeout_s and zero_poll_s must be positive", who));
  ScpiClientOptions c;
  c.timeout = ms(o.timeout_s);
  c.retries = o.retries;
  c.backoff = ms(std::max(o.backoff_s, 0.0));
  return c;
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t\"");
  const auto e = s.find_last_not_of(" \t\"");
  return b == std::string::npos ? std::string{} : s.substr(b, e - b + 1);
}

std::string format_number(double v) {
  return fmt::format("{}", v);
}

}  // namespace

ScpiPowerMeter::ScpiPowerMeter(std::unique_ptr<ScpiLink> link, std::string instrument,
                               const PowerMeterOptions& options)
    : client_(std::move(link), instrument, client_options(instrument, options)), options_(options) {}

void ScpiPowerMeter::set(const std::string& command) {
  const int reconnects = client_.reconnects();
  client_.command(command);
  if (!options_.check_errors) return;
  client_.check_errors(command);
  // The link was re-established while the setting was in flight: the instrument may never
  // have seen it. Settings are idempotent, so send it once more.
  if (client_.reconnects() != reconnects) {
    client_.command(command);
    client_.check_errors(command);
  }
}

Identity ScpiPowerMeter::identity() {
  const std::string answer = client_.query("*IDN?");
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const auto comma = answer.find(',', start);
    fields.push_back(trim(answer.substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (fields.size() != 4 || fields[0].empty() || fields[1].empty())
    throw ProtocolError(
        client_.instrument(), "*IDN?",
        fmt::format("expected \"vendor,model,serial,firmware\", the answer was \"{}\"", answer));
  // The client admits printable ASCII and tabs only; the tabs go too (see printable_text).
  return {printable_text(fields[0]), printable_text(fields[1]), printable_text(fields[2]),
          printable_text(fields[3])};
}

std::string ScpiPowerMeter::sensor_identity() {
  std::string s = client_.query("SYST:SENS:IDN?");
  if (s.empty())
    throw ProtocolError(client_.instrument(), "SYST:SENS:IDN?", "empty answer (no sensor attached?)");
  return printable_text(s);
}

void ScpiPowerMeter::set_wavelength_nm(double nm) {
  if (!(nm > 0.0) || !std::isfinite(nm))
    throw ConfigError(
        fmt::format("{}: wavelength must be a positive number of nm, got {}", client_.instrument(), nm));
  set("SENS:CORR:WAV " + format_number(nm));
}

void ScpiPowerMeter::set_auto_range(bool on) {
  set(on ? "SENS:POW:DC:RANG:AUTO ON" : "SENS:POW:DC:RANG:AUTO OFF");
}

void ScpiPowerMeter::set_averaging(int count) {
  if (count < 1)
    throw ConfigError(fmt::format("{}: averaging count must be >= 1, got {}", client_.instrument(), count));
  set(fmt::format("SENS:AVER:COUN {}", count));
  averaging_ = count;
}

void ScpiPowerMeter::zero() {
  set("SENS:CORR:COLL:ZERO:INIT");
  const auto deadline = Clock::now() + ms(options_.zero_timeout_s);
  for (;;) {
    const double state = client_.query_number("SENS:CORR:COLL:ZERO:STAT?");
    if (state == 0.0) break;
    if (state != 1.0)
      throw ProtocolError(client_.instrument(), "SENS:CORR:COLL:ZERO:STAT?",
                          fmt::format("expected 0 or 1, the answer was {}", state));
    if (Clock::now() >= deadline) {
      try {
        client_.command("SENS:CORR:COLL:ZERO:ABOR");
      } catch (const DeviceError&) {
      }
      throw TimeoutError(client_.instrument(), "SENS:CORR:COLL:ZERO:INIT",
                         fmt::format("zeroing still running after {} s", options_.zero_timeout_s));
    }
    std::this_thread::sleep_for(ms(options_.zero_poll_s));
  }
  if (options_.check_errors) client_.check_errors("SENS:CORR:COLL:ZERO:INIT");
}

PowerReading ScpiPowerMeter::reading_from(std::string_view query) {
  // A reading takes averaging x sample time inside the meter; wait that much longer.
  const auto extra = ms(averaging_ * options_.sample_time_s * 1.5);
  const std::string answer = client_.query(query, extra);
  const double v = parse_scpi_number(answer, client_.instrument(), std::string(query));
  PowerReading r;
  r.t_ns = monotonic_ns();
  auto refuse = [&](const std::string& why) {
    throw InvalidReading(client_.instrument(), std::string(query),
                         fmt::format("the answer \"{}\" is {}; not accepted as a measurement", answer, why));
  };
  // SCPI codes: +9.9E37 overflow (over range), 9.91E37 not-a-number, -9.9E37 negative overflow.
  if (std::abs(v - scpi_not_a_number) < 1e35) refuse("SCPI's not-a-number code");
  if (v <= -scpi_over_range) refuse("a negative overflow");
  if (v >= scpi_over_range || !std::isfinite(v)) {
    r.over_range = true;
    r.power_W = std::numeric_limits<double>::infinity();
    return r;
  }
  if (v < -options_.negative_tolerance_W) {
    refuse(fmt::format("a negative power (below -{:g} W, the zeroed sensor's noise)",
                       options_.negative_tolerance_W));
  }
  r.power_W = v;
  return r;
}

PowerReading ScpiPowerMeter::measure() {
  return reading_from("MEAS:POW?");
}
PowerReading ScpiPowerMeter::fetch() {
  return reading_from("FETC?");
}
PowerReading ScpiPowerMeter::read() {
  return reading_from("READ?");
}

void ScpiPowerMeter::configure_power() {
  set("CONF:POW");
}
void ScpiPowerMeter::initiate() {
  set("INIT");
}

void ScpiPowerMeter::reset() {
  client_.command("*RST");
  client_.drain_errors();  // a reset starts with an empty queue; stale entries are not ours
  averaging_ = 1;
}

double ScpiPowerMeter::wavelength_nm() {
  return client_.query_number("SENS:CORR:WAV?");
}

bool ScpiPowerMeter::auto_range() {
  const double v = client_.query_number("SENS:POW:DC:RANG:AUTO?");
  if (v != 0.0 && v != 1.0)
    throw ProtocolError(client_.instrument(), "SENS:POW:DC:RANG:AUTO?",
                        fmt::format("expected 0 or 1, got {}", v));
  return v == 1.0;
}

int ScpiPowerMeter::averaging() {
  const double v = client_.query_number("SENS:AVER:COUN?");
  if (v < 1.0 || v != std::floor(v))
    throw ProtocolError(client_.instrument(), "SENS:AVER:COUN?",
                        fmt::format("expected a count >= 1, got {}", v));
  averaging_ = static_cast<int>(v);
  return averaging_;
}

std::vector<ScpiErrorEntry> ScpiPowerMeter::errors() {
  return client_.drain_errors();
}

// ---- factories --------------------------------------------------------------------------

std::unique_ptr<ScpiPowerMeter> open_scpi_tcp_power_meter(const ScpiTcpAddress& a,
                                                          const PowerMeterOptions& o) {
  auto link = make_scpi_tcp_link(a);
  const std::string who = "power meter " + link->describe();
  auto meter = std::make_unique<ScpiPowerMeter>(std::move(link), who, o);
  meter->identity();
  return meter;
}

std::unique_ptr<ScpiPowerMeter> open_usbtmc_power_meter(UsbEndpointOpener opener, std::string description,
                                                        const PowerMeterOptions& o) {
  auto link = std::make_unique<usbtmc::Link>(std::move(opener), description);
  auto meter = std::make_unique<ScpiPowerMeter>(std::move(link), "power meter " + description, o);
  meter->identity();
  return meter;
}

std::unique_ptr<ScpiPowerMeter> open_usbtmc_power_meter(const UsbtmcAddress& a, const PowerMeterOptions& o) {
  if (a.product_id == 0) throw ConfigError("USBTMC power meter: no product id given");
  std::string model = usb_meter_model(a.vendor_id, a.product_id);
  const std::string description =
      fmt::format("USBTMC {:04x}:{:04x}{}{}{}", a.vendor_id, a.product_id, model.empty() ? "" : " " + model,
                  a.serial.empty() ? "" : " ", a.serial);
  return open_usbtmc_power_meter(libusb_endpoint_opener(a.vendor_id, a.product_id, a.serial), description, o);
}

std::unique_ptr<PowerMeter> connect_scpi_tcp_power_meter(const ScpiTcpAddress& a,
                                                         const PowerMeterOptions& o) {
  return open_scpi_tcp_power_meter(a, o);
}

std::unique_ptr<PowerMeter> connect_usbtmc_power_meter(const UsbtmcAddress& a, const PowerMeterOptions& o) {
  return open_usbtmc_power_meter(a, o);
}

}  // namespace tocd::devices
