#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "tocd/devices/instruments.hpp"
#include "tocd/devices/modbus_options.hpp"

namespace tocd::devices {

/// The mechanical tester entry of a lab config ([tester], transport "modbus-tcp").
struct TesterConfig {
  ModbusTcpAddress address;
  ModbusOptions link;
};

/// The vacuum controller entry of a lab config ([vacuum], transport "modbus-rtu").
struct VacuumConfig {
  ModbusRtuAddress address;
  ModbusOptions link;
};

/// The power meter entry of a lab config ([power_meter], transport "scpi-tcp" or "usbtmc").
struct PowerMeterConfig {
  enum class Transport { scpi_tcp, usbtmc };
  Transport transport = Transport::scpi_tcp;
  std::string host = "127.0.0.1";    ///< scpi-tcp
  int port = 5025;                   ///< scpi-tcp
  std::uint16_t vendor_id = 0x1313;  ///< usbtmc
  std::uint16_t product_id = 0;      ///< usbtmc; 0 = the first meter of that vendor
  std::string serial;                ///< usbtmc; empty = any
  double timeout_s = 2.0;
  int retries = 2;
  double wavelength_nm = 0.0;  ///< set on open when > 0
};

/// A parsed lab TOML (docs/instruments/lab-config.md): which instruments the rig has and how
/// to reach them. Any instrument may be absent.
struct LabConfig {
  std::string name;  ///< [lab] name, free text
  /// [lab] push_to: a lab server (postgresql:// URI) that `tocdlab run` pushes each run to
  /// after it ends; empty = none. The run always records into its local file first.
  std::string push_to;
  std::optional<TesterConfig> tester;
  std::optional<PowerMeterConfig> power_meter;
  std::optional<VacuumConfig> vacuum;
};

/// Parses lab TOML text. `source_name` (a file name) prefixes error messages, which name the
/// line and key that is wrong. Throws ConfigError, also when the text names no instrument.
LabConfig parse_lab_config(std::string_view toml_text, const std::string& source_name);

/// Reads and parses a lab TOML file. Throws ConfigError (also when the path cannot be read, is
/// a directory, is empty or larger than 1 MiB).
LabConfig load_lab_config(const std::filesystem::path& path);

/// Writes a config back as TOML that parse_lab_config reads to the same LabConfig.
std::string to_toml(const LabConfig& cfg);

struct LabInstruments {
  std::unique_ptr<MechanicalTester> tester;
  std::unique_ptr<PowerMeter> power_meter;
  std::unique_ptr<VacuumController> vacuum;
};  // any may be null

/// Connects to every instrument of the config. Throws the first DeviceError met (instruments
/// already opened are closed again).
LabInstruments open_lab(const LabConfig& cfg);

/// Connects to the power meter of a config entry (open_lab uses it).
std::unique_ptr<PowerMeter> open_power_meter(const PowerMeterConfig& cfg);

}  // namespace tocd::devices
