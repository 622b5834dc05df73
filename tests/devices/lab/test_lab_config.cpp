// Lab TOML parsing: fields, defaults, round trip, and errors that name the line and key.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"

using namespace tocd::devices;

namespace {

const char* kFull = R"(
[lab]
name = "pin rig 2"

[tester]
transport = "modbus-tcp"
host = "192.168.1.40"
port = 1502
slave_id = 3
timeout_s = 0.25
retries = 4

[power_meter]
transport = "usbtmc"
product_id = 0x8078
serial = "P0099"
wavelength_nm = 1300

[vacuum]
transport = "modbus-rtu"
device = "/dev/ttyUSB0"
baud = 9600
parity = "E"
slave_id = 7
)";

std::string error_of(const std::string& text) {
  try {
    parse_lab_config(text, "lab.toml");
  } catch (const tocd::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(LabConfig, ReadsEveryInstrument) {
  const LabConfig c = parse_lab_config(kFull, "lab.toml");
  EXPECT_EQ(c.name, "pin rig 2");
  ASSERT_TRUE(c.tester && c.power_meter && c.vacuum);
  EXPECT_EQ(c.tester->address.host, "192.168.1.40");
  EXPECT_EQ(c.tester->address.port, 1502);
  EXPECT_EQ(c.tester->address.slave_id, 3);
  EXPECT_DOUBLE_EQ(c.tester->link.timeout_s, 0.25);
  EXPECT_EQ(c.tester->link.retries, 4);
  EXPECT_DOUBLE_EQ(c.tester->link.backoff_s, ModbusOptions{}.backoff_s);
  EXPECT_EQ(c.power_meter->transport, PowerMeterConfig::Transport::usbtmc);
  EXPECT_EQ(c.power_meter->vendor_id, 0x1313);
  EXPECT_EQ(c.power_meter->product_id, 0x8078);
  EXPECT_EQ(c.power_meter->serial, "P0099");
  EXPECT_DOUBLE_EQ(c.power_meter->wavelength_nm, 1300.0);
  EXPECT_EQ(c.vacuum->address.device, "/dev/ttyUSB0");
  EXPECT_EQ(c.vacuum->address.baud, 9600);
  EXPECT_EQ(c.vacuum->address.parity, 'E');
  EXPECT_EQ(c.vacuum->address.slave_id, 7);
}

TEST(LabConfig, AnyInstrumentMayBeAbsent) {
  const LabConfig c = parse_lab_config("[tester]\nhost = \"h\"\n", "x");
  EXPECT_TRUE(c.tester);
  EXPECT_FALSE(c.power_meter);
  EXPECT_FALSE(c.vacuum);
  EXPECT_EQ(c.tester->address.port, 502);
}

TEST(LabConfig, RoundTripsThroughToml) {
  const LabConfig a = parse_lab_config(kFull, "lab.toml");
  const LabConfig b = parse_lab_config(to_toml(a), "round trip");
  EXPECT_EQ(to_toml(a), to_toml(b));
  EXPECT_EQ(b.vacuum->address.parity, 'E');
  EXPECT_EQ(b.power_meter->product_id, 0x8078);
}

TEST(LabConfig, ErrorsNameLineAndKey) {
  std::string e = error_of("[tester]\nhost = \"h\"\nport = 99999\n");
  EXPECT_NE(e.find("lab.toml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("[tester] port"), std::string::npos) << e;
  EXPECT_NE(e.find("1..65535"), std::string::npos) << e;

  e = error_of("[tester]\nhost = \"h\"\nprot = 5\n");
  EXPECT_NE(e.find("lab.toml:3: [tester] prot: unknown key"), std::string::npos) << e;

  e = error_of("[tester]\nport = 5\n");
  EXPECT_NE(e.find("host: is required"), std::string::npos) << e;

  e = error_of("[vacuum]\ndevice = \"/dev/x\"\nparity = \"Q\"\n");
  EXPECT_NE(e.find("lab.toml:3: [vacuum] parity"), std::string::npos) << e;

  e = error_of("[power_meter]\ntransport = \"gpib\"\n");
  EXPECT_NE(e.find("transport: must be \"scpi-tcp\" or \"usbtmc\""), std::string::npos) << e;

  e = error_of("[tester]\nhost = 5\n");
  EXPECT_NE(e.find("host: must be a string"), std::string::npos) << e;

  e = error_of("[tester]\nhost = \"h\"\ntimeout_s = -1\n");
  EXPECT_NE(e.find("timeout_s"), std::string::npos) << e;
}

TEST(LabConfig, UnknownInstrumentKindIsNamed) {
  const std::string e = error_of("\n[spectrometer]\nhost = \"h\"\n");
  EXPECT_NE(e.find("lab.toml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown instrument kind [spectrometer]"), std::string::npos) << e;
}

TEST(LabConfig, SyntaxErrorsCarryThePosition) {
  const std::string e = error_of("[tester]\nhost = \"h\nport = 1\n");
  EXPECT_EQ(e.rfind("lab.toml:2:", 0), 0u) << e;
}

TEST(LabConfig, MissingFileIsAConfigError) {
  EXPECT_THROW(load_lab_config("/nonexistent/lab.toml"), tocd::ConfigError);
}

}  // namespace
