// `tocdlab powermeter`: find USBTMC power meters and take one reading
// (docs/instruments/power-meter.md).
#include <charconv>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/power_meter_drivers.hpp"

namespace cli = tocd::cli;

namespace {

namespace dev = tocd::devices;

std::vector<std::uint16_t> known_products() {
  std::vector<std::uint16_t> ids;
  for (const auto& m : dev::known_usb_meters) ids.push_back(m.product_id);
  return ids;
}

void list_usb(bool json) {
  const dev::UsbScan scan = dev::scan_usb_devices(dev::thorlabs_vendor_id, known_products());
  if (json) {
    nlohmann::json out = {{"problem", scan.problem}, {"devices", nlohmann::json::array()}};
    for (const auto& d : scan.devices)
      out["devices"].push_back({{"vendor_id", fmt::format("{:04x}", d.vendor_id)},
                                {"product_id", fmt::format("{:04x}", d.product_id)},
                                {"model", d.model},
                                {"bus", d.bus},
                                {"address", d.address},
                                {"serial", d.serial},
                                {"note", d.note}});
    tocd::cli::print_json(out);
    return;
  }
  if (!scan.problem.empty()) {
    std::cout << "USB not available: " << scan.problem << '\n';
    return;
  }
  if (scan.devices.empty()) {
    std::cout
        << "no Thorlabs power meter (USB 1313:8078 PM100D, 1313:8072 PM100USB, 1313:807d PM400) attached\n";
    return;
  }
  for (const auto& d : scan.devices)
    std::cout << fmt::format("{:04x}:{:04x}  {:<9} bus {:03d} device {:03d}  serial {}{}\n", d.vendor_id,
                             d.product_id, d.model, d.bus, d.address, d.serial.empty() ? "?" : d.serial,
                             d.note.empty() ? "" : "  (" + d.note + ")");
}

struct ReadOptions {
  std::string tcp, usb;
  double wavelength_nm = 0, timeout_s = 2.0;
  int averaging = 0;
  bool json = false;
};

std::uint16_t parse_hex_id(const std::string& text, const std::string& what) {
  unsigned v = 0;
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v, 16);
  if (text.empty() || ec != std::errc{} || p != text.data() + text.size() || v > 0xFFFF)
    throw tocd::ConfigError(fmt::format("--usb: {} \"{}\" is not a 4-digit hex id", what, text));
  return static_cast<std::uint16_t>(v);
}

void read_once(const ReadOptions& o) {
  if (o.tcp.empty() == o.usb.empty())
    throw tocd::ConfigError("give exactly one of --tcp HOST[:PORT] or --usb VID:PID[:SERIAL]");
  dev::PowerMeterOptions po;
  po.timeout_s = o.timeout_s;
  std::unique_ptr<dev::ScpiPowerMeter> meter;
  if (!o.tcp.empty()) {
    dev::ScpiTcpAddress a;
    const auto colon = o.tcp.rfind(':');
    a.host = o.tcp.substr(0, colon);
    if (colon != std::string::npos) {
      const std::string port = o.tcp.substr(colon + 1);
      const auto [p, ec] = std::from_chars(port.data(), port.data() + port.size(), a.port);
      if (port.empty() || ec != std::errc{} || p != port.data() + port.size())
        throw tocd::ConfigError(fmt::format("--tcp: port \"{}\" is not a number", port));
    }
    meter = dev::open_scpi_tcp_power_meter(a, po);
  } else {
    dev::UsbtmcAddress a;
    const auto c1 = o.usb.find(':');
    if (c1 == std::string::npos) throw tocd::ConfigError("--usb: expected VID:PID[:SERIAL], e.g. 1313:8072");
    const auto c2 = o.usb.find(':', c1 + 1);
    a.vendor_id = parse_hex_id(o.usb.substr(0, c1), "vendor id");
    a.product_id = parse_hex_id(
        o.usb.substr(c1 + 1, c2 == std::string::npos ? std::string::npos : c2 - c1 - 1), "product id");
    if (c2 != std::string::npos) a.serial = o.usb.substr(c2 + 1);
    meter = dev::open_usbtmc_power_meter(a, po);
  }
  const dev::Identity id = meter->identity();
  const std::string sensor = meter->sensor_identity();
  if (o.wavelength_nm > 0) meter->set_wavelength_nm(o.wavelength_nm);
  if (o.averaging > 0) meter->set_averaging(o.averaging);
  const dev::PowerReading r = meter->measure();
  if (o.json) {
    nlohmann::json out = {{"vendor", id.vendor},     {"model", id.model}, {"serial", id.serial},
                          {"firmware", id.firmware}, {"sensor", sensor},  {"over_range", r.over_range},
                          {"t_ns", r.t_ns}};
    out["power_W"] = r.over_range ? nlohmann::json(nullptr) : nlohmann::json(r.power_W);
    tocd::cli::print_json(out);
  } else {
    std::cout << fmt::format("{} {} (serial {}, firmware {}), sensor {}\n", id.vendor, id.model, id.serial,
                             id.firmware, sensor);
    std::cout << (r.over_range ? std::string("power: OVER RANGE\n")
                               : fmt::format("power: {:.6g} W\n", r.power_W));
  }
}

void install_powermeter(CLI::App& root) {
  auto* cmd = root.add_subcommand("powermeter", "Optical power meter (USBTMC or SCPI over TCP)");
  cmd->require_subcommand(1);
  auto* list = cmd->add_subcommand("list-usb", "List attached Thorlabs power meters (vendor 0x1313)");
  auto list_json = std::make_shared<bool>(false);
  list->add_flag("--json", *list_json, "machine-readable output");
  list->callback([list_json] { list_usb(*list_json); });

  auto* read = cmd->add_subcommand("read", "Connect, print identity and one reading");
  auto o = std::make_shared<ReadOptions>();
  read->add_option("--tcp", o->tcp, "HOST[:PORT] of a meter speaking SCPI over TCP (port 5025 by default)");
  read->add_option("--usb", o->usb, "VID:PID[:SERIAL] of a USBTMC meter, e.g. 1313:8072");
  read->add_option("--wavelength", o->wavelength_nm, "set the correction wavelength (nm) first")
      ->check(cli::real_above(0.0, 100000.0));
  read->add_option("--averaging", o->averaging, "set the averaging count first")
      ->check(cli::whole_in(std::int64_t{1}, std::int64_t{1000000}));
  read->add_option("--timeout", o->timeout_s, "seconds per command")
      ->check(cli::real_above(0.0, 3600.0))
      ->capture_default_str();
  read->add_flag("--json", o->json, "machine-readable output");
  read->callback([o] { read_once(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(powermeter, install_powermeter);
