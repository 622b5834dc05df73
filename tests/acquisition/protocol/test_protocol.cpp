#include <string>

#include <gtest/gtest.h>

#include "tocd/acquisition/protocol.hpp"
#include "tocd/test/error_of.hpp"

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
  return tocd::test::error_of<ProtocolError>([&] { parse_protocol(text, "p.toml"); });
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

// Found by the protocol_toml fuzz target: an integer beyond 2^53 (no exact double) ended the
// program instead of being checked like any other number.
TEST(AcquisitionProtocol, IntegersBeyondADoublesPrecisionAreCheckedByValue) {
  auto msg =
      error_of(replace(kGood, "[0.25, 0.5, 1.0]", "{ from = 0.25, to = 1.5, count = 11111111111111111 }"));
  EXPECT_NE(msg.find("count"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1..10000"), std::string::npos) << msg;
  msg = error_of(replace(kGood, "hold_s = 2", "hold_s = 11111111111111111"));
  EXPECT_NE(msg.find("hold_s"), std::string::npos) << msg;
  // 2^53 + 1 in an array is read as 2^53 and refused by the thickness, naming the step.
  msg = error_of(replace(kGood, "[0.25, 0.5, 1.0]", "[0.25, 9007199254740993]"));
  EXPECT_NE(msg.find("step 2: displacement 9007199254740992 mm must lie in [0, thickness 2 mm)"),
            std::string::npos)
      << msg;
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

TEST(AcquisitionProtocol, EveryNumberIsBoundedAboveToo) {
  // Each message names file, line, key, the value, the accepted range and why.
  struct Case {
    const char* from;
    const char* to;
    const char* expect;
  };
  const Case cases[] = {
      {"hold_s = 2", "hold_s = 1e300",
       "p.toml:16: [steps] hold_s: must be <= 86400, got 1e+300; accepted: [0, 86400] s"},
      {"record_s = 3", "record_s = 1e300",
       "p.toml:17: [steps] record_s: must be <= 3600, got 1e+300; accepted: (0, 3600] s"},
      {"tester_Hz = 500", "tester_Hz = 1e-300",
       "p.toml:25: [rates] tester_Hz: must be >= 10, got 1e-300; accepted: [10, 10000] Hz (readings at least "
       "every "
       "0.1 s"},
      {"max_load_N = 30", "max_load_N = 1e300",
       "p.toml:29: [interlocks] max_load_N: must be <= 500, got 1e+300"},
      {"approach_speed_mm_per_s = 0.5", "approach_speed_mm_per_s = 25",
       "p.toml:12: [motion] approach_speed_mm_per_s: must be <= 5, got 25; accepted: (0, 5] mm/s"},
      {"thickness_mm = 2.0", "thickness_mm = 2000", "[sample] thickness_mm: must be <= 100, got 2000"},
      {"power_Hz = 20", "power_Hz = 0.01", "[rates] power_Hz: must be >= 1, got 0.01"},
      {"max_wait_s = 20", "max_wait_s = 1e9", "[settle] max_wait_s: must be <= 3600, got 1000000000"},
      {"power_W = 1.0e-3", "power_W = 1e300", "[baseline] power_W: must be <= 10, got 1e+300"},
  };
  for (const auto& c : cases) {
    const auto msg = error_of(replace(kGood, c.from, c.to));
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.to << " -> " << msg;
  }
}

TEST(AcquisitionProtocol, ThePollRateMustBoundTheTravelBetweenReadings) {
  // 5 mm/s at 50 Hz: 0.1 mm between two readings, over the 0.05 mm bound.
  const auto msg =
      error_of(replace(replace(kGood, "approach_speed_mm_per_s = 0.5", "approach_speed_mm_per_s = 5"),
                       "tester_Hz = 500", "tester_Hz = 50"));
  EXPECT_NE(msg.find("p.toml:25: [rates] tester_Hz: at 5 mm/s and 50 Hz the pin travels 0.1 mm between two "
                     "tester readings; it must be <= 0.05 mm"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("raise tester_Hz to >= 100 Hz"), std::string::npos) << msg;
  // The same speed at 100 Hz is accepted.
  EXPECT_NO_THROW(
      parse_protocol(replace(replace(kGood, "approach_speed_mm_per_s = 0.5", "approach_speed_mm_per_s = 5"),
                             "tester_Hz = 500", "tester_Hz = 100"),
                     "p.toml"));
}

TEST(AcquisitionProtocol, ARecordingWindowMustHoldAPowerReading) {
  const auto msg = error_of(replace(kGood, "record_s = 3", "record_s = 0.01"));
  EXPECT_NE(msg.find("p.toml:17: [steps] record_s: a 0.01 s window at power_Hz = 20 holds no power reading"),
            std::string::npos)
      << msg;
}

TEST(AcquisitionProtocol, StepValiditySettings) {
  const Protocol d = parse_protocol(kGood, "p.toml");
  EXPECT_DOUBLE_EQ(d.position_tolerance_mm, 0.01);
  EXPECT_DOUBLE_EQ(d.min_sample_fraction, 0.8);
  EXPECT_EQ(d.max_rerecords, 2);
  EXPECT_FALSE(d.interrupt_on_move_failure);
  const Protocol p = parse_protocol(
      replace(
          replace(
              kGood, "record_s = 3",
              "record_s = 3\nposition_tolerance_mm = 0.02\nmin_sample_fraction = 0.95\nmax_rerecords = 4"),
          "approach_speed_mm_per_s = 0.5", "approach_speed_mm_per_s = 0.5\non_move_failure = \"interrupt\""),
      "p.toml");
  EXPECT_DOUBLE_EQ(p.position_tolerance_mm, 0.02);
  EXPECT_DOUBLE_EQ(p.min_sample_fraction, 0.95);
  EXPECT_EQ(p.max_rerecords, 4);
  EXPECT_TRUE(p.interrupt_on_move_failure);
  EXPECT_NE(
      error_of(replace(kGood, "record_s = 3", "record_s = 3\nmax_rerecords = 1.5")).find("whole number"),
      std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "record_s = 3", "record_s = 3\nmin_sample_fraction = 1.5"))
                .find("[steps] min_sample_fraction: must be <= 1, got 1.5"),
            std::string::npos);
  EXPECT_NE(error_of(replace(kGood, "approach_speed_mm_per_s = 0.5", "on_move_failure = \"ignore\""))
                .find("[motion] on_move_failure: must be \"pause\" or \"interrupt\", got \"ignore\""),
            std::string::npos);
}

// A list is capped like a {from, to, count} range: 2,000,000 entries were accepted before.
TEST(AcquisitionProtocol, AListOfMoreThanTenThousandStepsIsRefusedLikeARange) {
  std::string many = "[";
  for (int i = 0; i < 10001; ++i) many += (i ? ", " : "") + std::string("0.25");
  many += "]";
  const auto msg = error_of(replace(kGood, "[0.25, 0.5, 1.0]", many));
  EXPECT_NE(msg.find("displacements_mm: has 10001 entries; at most 10000 are accepted"), std::string::npos)
      << msg.substr(0, 300);
}
