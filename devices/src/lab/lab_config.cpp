// Lab TOML: which instruments a rig has and how to reach them (docs/instruments/lab-config.md).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"

namespace tocd::devices {
namespace {

/// Reads one [table] of the lab file, remembering which keys were used so that a misspelt key
/// is reported instead of silently ignored.
class TableReader {
 public:
  TableReader(const toml::table& t, std::string name, const std::string& source)
      : t_(t), name_(std::move(name)), source_(source) {}

  [[noreturn]] void fail(const toml::node* at, const std::string& key, const std::string& what) const {
    const auto line = at ? at->source().begin.line : t_.source().begin.line;
    throw ConfigError(fmt::format("{}:{}: [{}] {}: {}", source_, line, name_, key, what));
  }

  std::string str(const std::string& key, std::string def, bool required = false) {
    const toml::node* n = find(key, required);
    if (!n) return def;
    if (const auto v = n->value<std::string>()) return *v;
    fail(n, key, "must be a string");
  }

  long long integer(const std::string& key, long long def, long long lo, long long hi) {
    const toml::node* n = find(key, false);
    if (!n) return def;
    const auto v = n->value_exact<std::int64_t>();
    if (!v) fail(n, key, "must be an integer");
    if (*v < lo || *v > hi) fail(n, key, fmt::format("must be in {}..{} (got {})", lo, hi, *v));
    return *v;
  }

  double number(const std::string& key, double def, double lo, double hi) {
    const toml::node* n = find(key, false);
    if (!n) return def;
    const auto v = n->value<double>();  // integers are accepted as numbers
    if (!v || !std::isfinite(*v)) fail(n, key, "must be a finite number");
    if (*v < lo || *v > hi) fail(n, key, fmt::format("must be in {}..{} (got {})", lo, hi, *v));
    return *v;
  }

  /// After reading: any key not asked for is a mistake.
  void reject_unknown() const {
    for (const auto& [k, v] : t_) {
      const std::string key(k.str());
      if (!used_.count(key)) fail(&v, key, "unknown key");
    }
  }

  ModbusOptions link(const ModbusOptions& def) {
    ModbusOptions o;
    o.timeout_s = number("timeout_s", def.timeout_s, 1e-3, 60.0);
    o.retries = static_cast<int>(integer("retries", def.retries, 0, 20));
    o.backoff_s = number("backoff_s", def.backoff_s, 0.0, 10.0);
    return o;
  }

 private:
  const toml::node* find(const std::string& key, bool required) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n && required) fail(nullptr, key, "is required");
    return n;
  }

  const toml::table& t_;
  std::string name_;
  const std::string& source_;
  std::set<std::string> used_;
};

void expect_transport(TableReader& r, const std::string& transport, const std::string& expected,
                      const toml::table& t) {
  if (transport != expected)
    r.fail(t.get("transport"), "transport", fmt::format("must be \"{}\" (got \"{}\")", expected, transport));
}

/// [tester] and [vacuum]: the one Modbus transport each accepts, the address (read by
/// `read_address` into the config's address) and the link options, in that order.
template <class Config, class ReadAddress>
Config read_modbus_instrument(const toml::table& t, const std::string& source, const char* name,
                              const char* transport, ReadAddress read_address) {
  TableReader r(t, name, source);
  expect_transport(r, r.str("transport", transport), transport, t);
  Config c;
  read_address(r, c.address);
  c.link = r.link({});
  r.reject_unknown();
  return c;
}

TesterConfig read_tester(const toml::table& t, const std::string& source) {
  return read_modbus_instrument<TesterConfig>(
      t, source, "tester", "modbus-tcp", [](TableReader& r, ModbusTcpAddress& a) {
        a.host = r.str("host", "", true);
        a.port = static_cast<int>(r.integer("port", 502, 1, 65535));
        a.slave_id = static_cast<int>(r.integer("slave_id", 1, 0, 255));
      });
}

VacuumConfig read_vacuum(const toml::table& t, const std::string& source) {
  return read_modbus_instrument<VacuumConfig>(
      t, source, "vacuum", "modbus-rtu", [&t](TableReader& r, ModbusRtuAddress& a) {
        a.device = r.str("device", "", true);
        a.baud = static_cast<int>(r.integer("baud", 19200, 50, 4000000));
        const std::string parity = r.str("parity", "N");
        if (parity != "N" && parity != "E" && parity != "O")
          r.fail(t.get("parity"), "parity", "must be \"N\", \"E\" or \"O\"");
        a.parity = parity[0];
        a.data_bits = static_cast<int>(r.integer("data_bits", 8, 5, 8));
        a.stop_bits = static_cast<int>(r.integer("stop_bits", 1, 1, 2));
        a.slave_id = static_cast<int>(r.integer("slave_id", 1, 1, 247));
      });
}

PowerMeterConfig read_power_meter(const toml::table& t, const std::string& source) {
  TableReader r(t, "power_meter", source);
  PowerMeterConfig c;
  const std::string transport = r.str("transport", "", true);
  if (transport == "scpi-tcp") {
    c.transport = PowerMeterConfig::Transport::scpi_tcp;
    c.host = r.str("host", "", true);
    c.port = static_cast<int>(r.integer("port", 5025, 1, 65535));
  } else if (transport == "usbtmc") {
    c.transport = PowerMeterConfig::Transport::usbtmc;
    c.vendor_id = static_cast<std::uint16_t>(r.integer("vendor_id", 0x1313, 0, 0xFFFF));
    c.product_id = static_cast<std::uint16_t>(r.integer("product_id", 0, 0, 0xFFFF));
    c.serial = r.str("serial", "");
  } else {
    r.fail(t.get("transport"), "transport",
           fmt::format("must be \"scpi-tcp\" or \"usbtmc\" (got \"{}\")", transport));
  }
  c.timeout_s = r.number("timeout_s", c.timeout_s, 1e-3, 60.0);
  c.retries = static_cast<int>(r.integer("retries", c.retries, 0, 20));
  c.wavelength_nm = r.number("wavelength_nm", 0.0, 0.0, 1e5);
  r.reject_unknown();
  return c;
}

}  // namespace

LabConfig parse_lab_config(std::string_view toml_text, const std::string& source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: {}", source_name, e.source().begin.line, e.source().begin.column,
                                  e.description()));
  }
  LabConfig cfg;
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    const auto* t = v.as_table();
    const auto line = v.source().begin.line;
    if (key != "lab" && key != "tester" && key != "power_meter" && key != "vacuum")
      throw ConfigError(
          fmt::format("{}:{}: unknown instrument kind [{}] (known: [lab], [tester], "
                      "[power_meter], [vacuum])",
                      source_name, line, key));
    if (!t) throw ConfigError(fmt::format("{}:{}: {} must be a table ([{}])", source_name, line, key, key));
    if (key == "lab") {
      TableReader r(*t, "lab", source_name);
      cfg.name = r.str("name", "");
      cfg.push_to = r.str("push_to", "");
      r.reject_unknown();
    } else if (key == "tester") {
      cfg.tester = read_tester(*t, source_name);
    } else if (key == "vacuum") {
      cfg.vacuum = read_vacuum(*t, source_name);
    } else {
      cfg.power_meter = read_power_meter(*t, source_name);
    }
  }
  // A lab without instruments probes nothing and runs nothing: almost always a wrong or
  // truncated file, so it is refused rather than treated as a lab that is all fine.
  if (!cfg.tester && !cfg.power_meter && !cfg.vacuum) {
    throw ConfigError(
        fmt::format("{}: no instruments: a lab config needs at least one of [tester], "
                    "[power_meter] or [vacuum]",
                    source_name));
  }
  return cfg;
}

LabConfig load_lab_config(const std::filesystem::path& path) {
  std::error_code ec;
  // An ifstream opens a directory without complaint and then reads nothing.
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(fmt::format("lab config {} is a directory, not a file", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("cannot read lab config {}", path.string()));
  // Lab files are a few hundred bytes; a large one is not a lab config (a device, a log).
  constexpr std::size_t kMaxBytes = 1 << 20;
  std::string text(kMaxBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw ConfigError(fmt::format("cannot read lab config {}", path.string()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxBytes)
    throw ConfigError(fmt::format("lab config {} is larger than {} bytes", path.string(), kMaxBytes));
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw ConfigError(fmt::format("lab config {} is empty", path.string()));
  return parse_lab_config(text, path.string());
}

namespace {

/// A TOML basic string of `text`, quotes and control characters escaped by toml++ itself, so
/// that a name holding `"` or an ESC reads back as written and cannot add keys of its own.
/// No format flags: with its defaults toml++ writes a text that starts with a newline as a
/// multi-line literal string, and TOML drops the newline right after the opening delimiter
/// when the config is read back.
std::string toml_string(const std::string& text) {
  std::ostringstream out;
  out << toml::toml_formatter{toml::value<std::string>(text), toml::format_flags::none};
  return out.str();
}

}  // namespace

std::string to_toml(const LabConfig& cfg) {
  std::string out;
  auto link = [&](const ModbusOptions& o) {
    out += fmt::format("timeout_s = {}\nretries = {}\nbackoff_s = {}\n", o.timeout_s, o.retries, o.backoff_s);
  };
  if (!cfg.name.empty() || !cfg.push_to.empty()) {
    out += "[lab]\n";
    if (!cfg.name.empty()) out += fmt::format("name = {}\n", toml_string(cfg.name));
    if (!cfg.push_to.empty()) out += fmt::format("push_to = {}\n", toml_string(cfg.push_to));
    out += "\n";
  }
  if (cfg.tester) {
    const auto& a = cfg.tester->address;
    out += fmt::format("[tester]\ntransport = \"modbus-tcp\"\nhost = {}\nport = {}\nslave_id = {}\n",
                       toml_string(a.host), a.port, a.slave_id);
    link(cfg.tester->link);
    out += "\n";
  }
  if (cfg.power_meter) {
    const auto& p = *cfg.power_meter;
    if (p.transport == PowerMeterConfig::Transport::scpi_tcp)
      out += fmt::format("[power_meter]\ntransport = \"scpi-tcp\"\nhost = {}\nport = {}\n",
                         toml_string(p.host), p.port);
    else
      out += fmt::format(
          "[power_meter]\ntransport = \"usbtmc\"\nvendor_id = 0x{:04x}\nproduct_id = 0x{:04x}\n"
          "serial = {}\n",
          p.vendor_id, p.product_id, toml_string(p.serial));
    out += fmt::format("timeout_s = {}\nretries = {}\n", p.timeout_s, p.retries);
    if (p.wavelength_nm > 0) out += fmt::format("wavelength_nm = {}\n", p.wavelength_nm);
    out += "\n";
  }
  if (cfg.vacuum) {
    const auto& a = cfg.vacuum->address;
    out += fmt::format(
        "[vacuum]\ntransport = \"modbus-rtu\"\ndevice = {}\nbaud = {}\nparity = \"{}\"\n"
        "data_bits = {}\nstop_bits = {}\nslave_id = {}\n",
        toml_string(a.device), a.baud, a.parity, a.data_bits, a.stop_bits, a.slave_id);
    link(cfg.vacuum->link);
  }
  return out;
}

}  // namespace tocd::devices
