// Power readings that cannot be a measurement (negative power, SCPI's not-a-number and
// negative-overflow codes) are refused with an InvalidReading naming the meter and the answer;
// noise around zero and over-range keep their meaning.
#include <chrono>
#include <limits>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "tocd/devices/errors.hpp"
#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/devices/scpi_link.hpp"
#include "tocd/test/error_of.hpp"

namespace dev = tocd::devices;

namespace {

// Answers every query with the same fixed text.
class FixedAnswerLink : public dev::ScpiLink {
 public:
  explicit FixedAnswerLink(std::string answer) : answer_(std::move(answer)) {}
  std::string describe() const override { return "fake"; }
  void open(dev::Clock::time_point) override { open_ = true; }
  void close() noexcept override { open_ = false; }
  bool is_open() const noexcept override { return open_; }
  void write(std::string_view, dev::Clock::time_point) override {}
  std::string read(dev::Clock::time_point) override { return answer_; }
  void clear(dev::Clock::time_point) override {}

 private:
  std::string answer_;
  bool open_ = false;
};

dev::PowerReading measure(const std::string& answer) {
  dev::ScpiPowerMeter meter(std::make_unique<FixedAnswerLink>(answer), "power meter PM-7", {});
  return meter.measure();
}

std::string refusal(const std::string& answer) {
  return tocd::test::error_of<dev::InvalidReading>([&] { measure(answer); });
}

}  // namespace

TEST(PowerReadings, NegativePowerIsRefusedNamingMeterAndAnswer) {
  const std::string e = refusal("-2.5E-3");
  EXPECT_NE(e.find("power meter PM-7: MEAS:POW?: the answer \"-2.5E-3\" is a negative power"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("below -1e-06 W"), std::string::npos) << e;
  EXPECT_NE(refusal("-1.1E-6"), "");
  // InvalidReading is a ProtocolError, so code that handles bad answers handles it too.
  EXPECT_THROW(measure("-1"), dev::ProtocolError);
}

TEST(PowerReadings, SpecialScpiCodesAreNotMeasurements) {
  EXPECT_NE(refusal("9.91E37").find("SCPI's not-a-number code"), std::string::npos);
  EXPECT_NE(refusal("-9.9E37").find("a negative overflow"), std::string::npos);
  const dev::PowerReading over = measure("9.9E37");
  EXPECT_TRUE(over.over_range);
  EXPECT_EQ(over.power_W, std::numeric_limits<double>::infinity());
}

TEST(PowerReadings, NoiseAroundZeroAndNormalReadingsAreKept) {
  EXPECT_DOUBLE_EQ(measure("-3.0E-10").power_W, -3.0e-10);  // a zeroed sensor in the dark
  EXPECT_DOUBLE_EQ(measure("-1.0E-6").power_W, -1.0e-6);    // the tolerance itself
  EXPECT_DOUBLE_EQ(measure("0").power_W, 0.0);
  const dev::PowerReading r = measure("1.234E-3");
  EXPECT_DOUBLE_EQ(r.power_W, 1.234e-3);
  EXPECT_FALSE(r.over_range);
}

TEST(PowerReadings, ToleranceIsConfigurableWithinLimits) {
  dev::PowerMeterOptions strict;
  strict.negative_tolerance_W = 0.0;
  dev::ScpiPowerMeter meter(std::make_unique<FixedAnswerLink>("-1E-12"), "pm", strict);
  EXPECT_THROW(meter.measure(), dev::InvalidReading);
  dev::PowerMeterOptions bad;
  bad.negative_tolerance_W = -1.0;
  EXPECT_THROW(dev::ScpiPowerMeter(std::make_unique<FixedAnswerLink>("0"), "pm", bad), tocd::ConfigError);
}
