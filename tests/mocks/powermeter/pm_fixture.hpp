#pragma once

#include <atomic>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/mocks/power_meter_twin.hpp"

namespace pmtest {

enum class Wire { tcp, usb };

inline std::string wire_name(const testing::TestParamInfo<Wire>& i) {
  return i.param == Wire::tcp ? "Tcp" : "Usb";
}

/// A simulated meter with controllable light, and a driver talking to it over `GetParam()`.
class MeterOverWire : public testing::TestWithParam<Wire> {
 protected:
  void SetUp() override { start({}); }

  void start(tocd::mocks::PowerMeterTwinOptions o) {
    o.power_W = [this] { return light_W.load(); };
    twin = std::make_unique<tocd::mocks::PowerMeterTwin>(o);
    if (GetParam() == Wire::tcp) twin->serve_tcp();
    meter = open();
  }

  std::unique_ptr<tocd::devices::ScpiPowerMeter> open() {
    if (GetParam() == Wire::tcp)
      return tocd::devices::open_scpi_tcp_power_meter(twin->tcp_address(), options);
    return tocd::devices::open_usbtmc_power_meter(twin->usb_opener(), "simulated USBTMC", options);
  }

  static tocd::devices::PowerMeterOptions fast_options() {
    tocd::devices::PowerMeterOptions o;
    o.timeout_s = 0.2;  // every injected timeout costs this much; keep the suite quick
    o.retries = 2;
    o.backoff_s = 0.005;
    o.zero_poll_s = 0.01;
    o.zero_timeout_s = 2.0;
    return o;
  }

  std::atomic<double> light_W{1e-3};
  tocd::devices::PowerMeterOptions options = fast_options();
  std::unique_ptr<tocd::mocks::PowerMeterTwin> twin;
  std::unique_ptr<tocd::devices::ScpiPowerMeter> meter;
};

}  // namespace pmtest
