// Lab TOML parsing: fields, defaults, round trip, and errors that name the line and key.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/test/error_of.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

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
  return tocd::test::error_of<tocd::ConfigError>([&] { parse_lab_config(text, "lab.toml"); });
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

// Found by the lab_toml fuzz target: to_toml wrote strings between quotes as they were, so a
// name with an ESC (or a quote) made a file that parse_lab_config refused, or one with keys
// the name had smuggled in.
TEST(LabConfig, RoundTripKeepsQuotesAndControlCharactersInStrings) {
  LabConfig a = parse_lab_config("[tester]\nhost = \"h\"\n", "lab.toml");
  a.name = "rig \"1\"\x1b[31m\n[vacuum]\ndevice = \"x\"";
  a.tester->address.host = "back\\slash";
  const LabConfig b = parse_lab_config(to_toml(a), "round trip");
  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.tester->address.host, "back\\slash");
  EXPECT_FALSE(b.vacuum);
}

// Found by the lab_toml fuzz target in CI: a name that starts with a newline was written as a
// multi-line literal string, and reading it back drops the newline after the opening '''.
TEST(LabConfig, RoundTripKeepsALeadingNewline) {
  LabConfig a = parse_lab_config("[tester]\nhost = \"h\"\n", "lab.toml");
  a.name = "\nrig";
  a.tester->address.host = "\n::1";
  const LabConfig b = parse_lab_config(to_toml(a), "round trip");
  EXPECT_EQ(b.name, "\nrig");
  EXPECT_EQ(b.tester->address.host, "\n::1");
}

// [lab] push_to names the server `tocdlab run` pushes each run to (docs/database.md).
TEST(LabConfig, PushToIsReadAndWrittenBack) {
  const LabConfig a = parse_lab_config(
      "[lab]\npush_to = \"postgresql://rig1@lab-db/lab\"\n[tester]\nhost = \"h\"\n", "lab.toml");
  EXPECT_EQ(a.push_to, "postgresql://rig1@lab-db/lab");
  EXPECT_TRUE(a.name.empty());
  EXPECT_EQ(parse_lab_config(to_toml(a), "round trip").push_to, a.push_to);
  EXPECT_TRUE(parse_lab_config(kFull, "lab.toml").push_to.empty());
  EXPECT_NE(error_of("[lab]\npush_to = 5\n[tester]\nhost = \"h\"\n").find("push_to"), std::string::npos);
}

TEST(LabConfig, ErrorsNameLineAndKey) {
  // Each file, and what its error message must say.
  const struct {
    const char* toml;
    std::vector<std::string> says;
  } cases[] = {
      {"[tester]\nhost = \"h\"\nport = 99999\n", {"lab.toml:3", "[tester] port", "1..65535"}},
      {"[tester]\nhost = \"h\"\nprot = 5\n", {"lab.toml:3: [tester] prot: unknown key"}},
      {"[tester]\nport = 5\n", {"host: is required"}},
      {"[vacuum]\ndevice = \"/dev/x\"\nparity = \"Q\"\n", {"lab.toml:3: [vacuum] parity"}},
      {"[power_meter]\ntransport = \"gpib\"\n", {"transport: must be \"scpi-tcp\" or \"usbtmc\""}},
      {"[tester]\nhost = 5\n", {"host: must be a string"}},
      {"[tester]\nhost = \"h\"\ntimeout_s = -1\n", {"timeout_s"}},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.toml);
    for (const auto& part : c.says) EXPECT_NE(e.find(part), std::string::npos) << c.toml << "\n-> " << e;
  }
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

std::string load_error(const std::filesystem::path& path) {
  return tocd::test::error_of<tocd::ConfigError>([&] { load_lab_config(path); });
}

TEST(LabConfig, EmptyFileDirectoryAndNoInstrumentsAreRefused) {
  const tocd::test::TempDir dir("lab_cfg");
  const std::string as_dir = load_error(dir);
  EXPECT_NE(as_dir.find(dir.path().string() + " is a directory, not a file"), std::string::npos) << as_dir;

  ASSERT_TRUE(tocd::test::write_file(dir / "empty.toml", ""));
  const std::string empty = load_error(dir / "empty.toml");
  EXPECT_NE(empty.find("empty.toml is empty"), std::string::npos) << empty;
  ASSERT_TRUE(tocd::test::write_file(dir / "blank.toml", "\n  \n\t\n"));
  EXPECT_NE(load_error(dir / "blank.toml").find("blank.toml is empty"), std::string::npos);

  ASSERT_TRUE(tocd::test::write_file(dir / "name_only.toml", "# a rig\n[lab]\nname = \"rig\"\n"));
  const std::string none = load_error(dir / "name_only.toml");
  EXPECT_NE(none.find("name_only.toml: no instruments"), std::string::npos) << none;
  EXPECT_NE(error_of("").find("lab.toml: no instruments"), std::string::npos);

  ASSERT_TRUE(tocd::test::write_file(dir / "big.toml", std::string((1 << 20) + 10, '#')));
  EXPECT_NE(load_error(dir / "big.toml").find("larger than 1048576 bytes"), std::string::npos);
}

}  // namespace
