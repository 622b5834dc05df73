#include <string>

#include <gtest/gtest.h>

#include "tocd/acquisition/protocol.hpp"

using namespace tocd::acquisition;

namespace {

const std::string kGood = R"(name = "pin compression"
[sample]
tissue = "porcine skin"
thickness_mm = 2.0
notes = "flank"

[baseline]
power_W = 1.0e-3

[motion]
contact_position_mm = 1.0
approach_speed_mm_per_s = 0.5

[steps]
displacements_mm = [0.25, 0.5, 1.0]
hold_s = 2
record_s = 3

[settle]
max_rate = 0.02
window_s = 0.5
max_wait_s = 20

[rates]
tester_Hz = 500
power_Hz = 20

[interlocks]
max_load_N = 30
)";

std::string error_of(const std::string& text) {
  try {
    parse_protocol(text, "p.toml");
  } catch (const ProtocolError& e) {
    return e.what();
  }
  return "no error";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

}  // namespace

TEST(AcquisitionProtocol, ParsesEveryTable) {
  const Protocol p = parse_protocol(kGood, "p.toml");
  EXPECT_EQ(p.name, "pin compression");
  EXPECT_EQ(p.sample.tissue, "porcine skin");
  EXPECT_DOUBLE_EQ(p.sample.thickness_mm, 2.0);
  ASSERT_TRUE(p.baseline.power_W);
  EXPECT_DOUBLE_EQ(*p.baseline.power_W, 1e-3);
  EXPECT_FALSE(p.baseline.measure);
  EXPECT_EQ(p.kind, StepKind::displacement);
  ASSERT_EQ(p.steps.size(), 3u);
  EXPECT_DOUBLE_EQ(p.steps[2].displacement_mm, 1.0);
  EXPECT_DOUBLE_EQ(p.steps[2].nominal_strain, 0.5);
  EXPECT_EQ(p.steps[2].index, 2);
  EXPECT_DOUBLE_EQ(p.contact_position_mm, 1.0);
  EXPECT_DOUBLE_EQ(p.hold_s, 2.0);
  EXPECT_DOUBLE_EQ(p.record_s, 3.0);
  EXPECT_DOUBLE_EQ(p.settle.max_rate, 0.02);
  EXPECT_DOUBLE_EQ(p.rates.tester_Hz, 500.0);
  EXPECT_DOUBLE_EQ(p.rates.power_Hz, 20.0);
  EXPECT_DOUBLE_EQ(p.rates.pressure_Hz, 10.0);  // default
  EXPECT_DOUBLE_EQ(p.interlocks.max_load_N, 30.0);
  EXPECT_EQ(p.source_text, kGood);
  // 1 mm of travel at 0.5 mm/s + 3 x (0.5 + 2 + 3) s
  EXPECT_NEAR(p.nominal_duration_s(), 2.0 + 3 * 5.5, 1e-12);
}

TEST(AcquisitionProtocol, StrainsBecomeDisplacements) {
  const auto p =
      parse_protocol(replace(kGood, "displacements_mm = [0.25, 0.5, 1.0]", "strains = [0.1, 0.6]"), "p.toml");
  EXPECT_EQ(p.kind, StepKind::strain);
  ASSERT_EQ(p.steps.size(), 2u);
  EXPECT_DOUBLE_EQ(p.steps[1].displacement_mm, 1.2);
  EXPECT_DOUBLE_EQ(p.steps[1].nominal_strain, 0.6);
}

TEST(AcquisitionProtocol, RangeOfSteps) {
  const auto p =
      parse_protocol(replace(kGood, "[0.25, 0.5, 1.0]", "{ from = 0.25, to = 1.5, count = 6 }"), "p.toml");
  ASSERT_EQ(p.steps.size(), 6u);
  EXPECT_DOUBLE_EQ(p.steps[0].displacement_mm, 0.25);
  EXPECT_DOUBLE_EQ(p.steps[5].displacement_mm, 1.5);
  EXPECT_DOUBLE_EQ(p.steps[1].displacement_mm, 0.5);
}

TEST(AcquisitionProtocol, VacuumSteps) {
  const auto p = parse_protocol(
      replace(kGood, "displacements_mm = [0.25, 0.5, 1.0]", "vacuum_kPa = [80, 60]"), "p.toml");
  EXPECT_EQ(p.kind, StepKind::vacuum);
  EXPECT_DOUBLE_EQ(p.steps[1].pressure_kPa, 60.0);
  EXPECT_DOUBLE_EQ(p.steps[1].displacement_mm, 0.0);
}

TEST(AcquisitionProtocol, MeasuredBaseline) {
  const auto p =
      parse_protocol(replace(kGood, "power_W = 1.0e-3", "measure = true\nmeasure_s = 4"), "p.toml");
  EXPECT_TRUE(p.baseline.measure);
  EXPECT_FALSE(p.baseline.power_W);
  EXPECT_DOUBLE_EQ(p.baseline.measure_s, 4.0);
}

TEST(AcquisitionProtocol, MalformedTomlNamesLineAndColumn) {
  const auto msg = error_of(replace(kGood, "hold_s = 2", "hold_s = = 2"));
  EXPECT_NE(msg.find("p.toml:16:"), std::string::npos) << msg;
}

TEST(AcquisitionProtocol, WrongTypeNamesLineAndKey) {
  const auto msg = error_of(replace(kGood, "record_s = 3", "record_s = \"three\""));
  EXPECT_NE(msg.find("p.toml:17:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[steps] record_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must be a number"), std::string::npos) << msg;
}

TEST(AcquisitionProtocol, UnknownKeyIsRejected) {
  const auto msg = error_of(replace(kGood, "hold_s = 2", "hold_S = 2"));
  EXPECT_NE(msg.find("p.toml:16: [steps] hold_S: unknown key"), std::string::npos) << msg;
}

TEST(AcquisitionProtocol, ZeroOrNegativeBaselineIsAnError) {
  for (const char* v : {"0.0", "-1e-3"}) {
    const auto msg = error_of(replace(kGood, "power_W = 1.0e-3", std::string("power_W = ") + v));
    EXPECT_NE(msg.find("p.toml:8: [baseline] power_W"), std::string::npos) << msg;
    EXPECT_NE(msg.find("must be > 0 W"), std::string::npos) << msg;
  }
}

TEST(AcquisitionProtocol, BaselineNeedsExactlyOneSource) {
  EXPECT_NE(error_of(replace(kGood, "power_W = 1.0e-3", "")).find("either power_W"), std::string::npos);
  EXPECT_NE(
      error_of(replace(kGood, "power_W = 1.0e-3", "power_W = 1.0\nmeasure = true")).find("either power_W"),
      std::string::npos);
}

TEST(AcquisitionProtocol, MissingTablesAndKeys) {
  EXPECT_NE(error_of(replace(kGood, "[sample]", "[sampel]")).find("unknown key"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "thickness_mm = 2.0", "")).find("[sample] thickness_mm: missing"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "displacements_mm = [0.25, 0.5, 1.0]", "")).find("exactly one of"),
            std::string::npos);
}

TEST(AcquisitionProtocol, OutOfRangeValues) {
  EXPECT_NE(error_of(replace(kGood, "[0.25, 0.5, 1.0]", "[0.25, 2.5]")).find("step 2: displacement 2.5 mm"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "[0.25, 0.5, 1.0]", "[]")).find("at least one value"), std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "hold_s = 2", "hold_s = -1")).find("must be >= 0, got -1"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "tester_Hz = 500", "tester_Hz = 0")).find("[rates] tester_Hz"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "max_load_N = 30", "max_load_N = -3")).find("[interlocks] max_load_N"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "[0.25, 0.5, 1.0]", "{ from = 0.25, to = 1.5, count = 2.5 }"))
                .find("count: must be a whole number"),
            std::string::npos);
}

TEST(AcquisitionProtocol, MissingFileIsAProtocolError) {
  EXPECT_THROW(load_protocol("/nonexistent/protocol.toml"), ProtocolError);
}
