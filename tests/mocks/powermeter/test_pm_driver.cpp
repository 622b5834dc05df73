// Every driver operation against the simulated meter, over TCP and over USBTMC.
#include <cmath>
#include <numeric>
#include <vector>

#include "pm_fixture.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/test/device_identity.hpp"

using namespace pmtest;
using tocd::ConfigError;

TEST_P(MeterOverWire, IdentityAndSensor) {
  EXPECT_EQ(meter->identity(), (tocd::devices::Identity{"Thorlabs", "PM100USB", "P0012345", "1.6.0"}));
  EXPECT_EQ(meter->sensor_identity().substr(0, 6), "S121C,");
}

TEST_P(MeterOverWire, SettingsReachTheMeterAndReadBack) {
  meter->set_wavelength_nm(850);
  meter->set_averaging(10);
  meter->set_auto_range(false);
  EXPECT_DOUBLE_EQ(twin->wavelength_nm(), 850.0);
  EXPECT_EQ(twin->averaging(), 10);
  EXPECT_FALSE(twin->auto_range());
  EXPECT_DOUBLE_EQ(meter->wavelength_nm(), 850.0);
  EXPECT_EQ(meter->averaging(), 10);
  EXPECT_FALSE(meter->auto_range());
  meter->set_auto_range(true);
  EXPECT_TRUE(meter->auto_range());
  meter->reset();
  EXPECT_DOUBLE_EQ(twin->wavelength_nm(), 635.0);
  EXPECT_EQ(twin->averaging(), 1);
  EXPECT_TRUE(meter->errors().empty());
}

TEST_P(MeterOverWire, OutOfRangeSettingIsAnInstrumentFaultNamingTheCommand) {
  try {
    meter->set_wavelength_nm(2000);  // the S121C covers 400..1100 nm
    FAIL();
  } catch (const tocd::devices::InstrumentFault& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("SENS:CORR:WAV 2000"), std::string::npos) << m;
    EXPECT_NE(m.find("-222"), std::string::npos) << m;
  }
  EXPECT_DOUBLE_EQ(twin->wavelength_nm(), 635.0);
  EXPECT_THROW(meter->set_averaging(0), ConfigError);
  EXPECT_THROW(meter->set_wavelength_nm(std::nan("")), ConfigError);
}

TEST_P(MeterOverWire, ReadingsFollowTheLightWithTimestamps) {
  light_W = 2.5e-4;
  const auto t0 = tocd::monotonic_ns();
  const auto a = meter->measure();
  EXPECT_FALSE(a.over_range);
  // dark offset 5 nW + 0.2 % noise: 10 sigma of the relative noise
  EXPECT_NEAR(a.power_W, 2.5e-4, 2.5e-4 * 0.02 + 1e-8);
  EXPECT_GE(a.t_ns, t0);
  light_W = 1e-6;
  meter->configure_power();
  meter->initiate();
  const auto b = meter->fetch();
  EXPECT_NEAR(b.power_W, 1e-6, 1e-6 * 0.02 + 1e-8);
  EXPECT_GE(b.t_ns, a.t_ns);
  const auto c = meter->read();
  EXPECT_NEAR(c.power_W, 1e-6, 1e-6 * 0.02 + 1e-8);
}

TEST_P(MeterOverWire, ZeroingRemovesTheDarkOffset) {
  light_W = 0.0;
  // Before zeroing the dark reading sits at the 5 nW offset (noise 0.2 nW per sample).
  meter->set_averaging(4);
  EXPECT_NEAR(meter->measure().power_W, 5e-9, 1e-9);
  const auto t0 = tocd::monotonic_ns();
  meter->zero();
  // The twin's zeroing takes 0.4 s of simulated (= real, factor 1) time; zero() waits for it.
  EXPECT_GE(tocd::monotonic_ns() - t0, 350'000'000);
  EXPECT_NEAR(meter->measure().power_W, 0.0, 1e-9);
}

TEST_P(MeterOverWire, AveragingNarrowsTheNoise) {
  tocd::mocks::PowerMeterTwinOptions o;
  o.noise_relative = 0.01;
  o.sample_time_s = 0.0;  // the spread, not the timing, is tested here
  meter.reset();
  twin.reset();
  start(o);
  light_W = 1e-3;
  const auto spread = [&](int count) {
    meter->set_averaging(count);
    std::vector<double> v(60);
    for (auto& x : v) x = meter->read().power_W;
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
    double ss = 0;
    for (double x : v) ss += (x - mean) * (x - mean);
    return std::sqrt(ss / (v.size() - 1));
  };
  const double s1 = spread(1), s100 = spread(100);
  // Expected 1e-5 and 1e-6; the sample sd of 60 values is within +-30 % at ~2.3 sigma.
  EXPECT_NEAR(s1, 1e-5, 0.3e-5);
  EXPECT_NEAR(s100, 1e-6, 0.3e-6);
}

TEST_P(MeterOverWire, WavelengthCorrectionScalesTheReading) {
  tocd::mocks::PowerMeterTwinOptions o;
  o.light_wavelength_nm = 800.0;
  o.noise_relative = 0.0;
  meter.reset();
  twin.reset();
  start(o);
  light_W = 1e-3;
  meter->zero();
  meter->set_wavelength_nm(800);
  const double right = meter->measure().power_W;
  meter->set_wavelength_nm(400);
  const double wrong = meter->measure().power_W;
  EXPECT_NEAR(right, 1e-3, 1e-8);
  EXPECT_NEAR(wrong / right, 2.0, 1e-4);  // ideal silicon responsivity ~ lambda
}

TEST_P(MeterOverWire, OverRangeIsFlaggedNotANumber) {
  light_W = 1.0;  // above the 0.5 W sensor limit
  auto r = meter->measure();
  EXPECT_TRUE(r.over_range);
  EXPECT_TRUE(std::isinf(r.power_W));
  // A fixed range saturates: set it at 1e-4 W light, then let the light rise 100x.
  light_W = 5e-5;
  meter->measure();  // auto range picks the 1e-4 W decade
  meter->set_auto_range(false);
  light_W = 5e-3;
  EXPECT_TRUE(meter->measure().over_range);
  meter->set_auto_range(true);
  r = meter->measure();
  EXPECT_FALSE(r.over_range);
  EXPECT_NEAR(r.power_W, 5e-3, 1e-4);
}

TEST_P(MeterOverWire, GenericFactoriesGiveTheSameDriver) {
  std::unique_ptr<tocd::devices::PowerMeter> pm =
      GetParam() == Wire::tcp ? tocd::devices::connect_scpi_tcp_power_meter(twin->tcp_address(), options)
                              : tocd::devices::open_usbtmc_power_meter(twin->usb_opener(), "sim", options);
  EXPECT_EQ(pm->identity().model, "PM100USB");
  pm->set_averaging(2);
  EXPECT_GT(pm->measure().power_W, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Wires, MeterOverWire, testing::Values(Wire::tcp, Wire::usb), wire_name);

TEST(PowerMeterConnect, NobodyListeningIsAConnectionErrorWithinTheBound) {
  tocd::devices::PowerMeterOptions o;
  o.timeout_s = 0.2;
  o.retries = 1;
  o.backoff_s = 0.01;
  // An ephemeral port that was just free: bind, read the port, close.
  tocd::mocks::PowerMeterTwin t;
  const int port = t.serve_tcp();
  t.stop_tcp();
  const auto t0 = tocd::monotonic_ns();
  try {
    tocd::devices::open_scpi_tcp_power_meter({"127.0.0.1", port}, o);
    FAIL();
  } catch (const tocd::devices::ConnectionError& e) {
    EXPECT_NE(std::string(e.what()).find("*IDN?"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::to_string(port)), std::string::npos) << e.what();
  }
  EXPECT_LT(tocd::monotonic_ns() - t0, 2'000'000'000);
}

TEST(PowerMeterConnect, UnpluggedUsbMeterIsAConnectionError) {
  tocd::mocks::PowerMeterTwin t;
  t.set_usb_unplugged(true);
  tocd::devices::PowerMeterOptions o;
  o.retries = 1;
  o.backoff_s = 0.01;
  EXPECT_THROW(tocd::devices::open_usbtmc_power_meter(t.usb_opener(), "sim", o),
               tocd::devices::ConnectionError);
  EXPECT_THROW(tocd::devices::connect_scpi_tcp_power_meter({"", 5025}), ConfigError);
  EXPECT_THROW(tocd::devices::connect_usbtmc_power_meter({0x1313, 0, ""}), ConfigError);
}
