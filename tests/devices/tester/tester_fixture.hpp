#pragma once

#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "tocd/core/clock.hpp"
#include "tocd/devices/tester_driver.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/tester_twin.hpp"

// A tester twin on loopback running 50x faster than real time, and a driver connected to it.
class TesterTest : public ::testing::Test {
 protected:
  static constexpr double kClockFactor = 50.0;

  void SetUp() override {
    clock_ = std::make_shared<tocd::mocks::SimClock>(kClockFactor);
    tocd::mocks::TesterTwinOptions o;
    o.clock = clock_;
    o.physics.tissue = tocd::mocks::make_analytic_tissue(2.5);
    o.physics.load_noise_N = 0.0;
    twin_ = std::make_unique<tocd::mocks::TesterTwin>(o);
    tester_ = tocd::devices::connect_modbus_tcp_tester(twin_->address(), options());
  }

  tocd::devices::ModbusOptions options(int retries = 2) const {
    tocd::devices::ModbusOptions opt;
    opt.timeout_s = 0.2;
    opt.retries = retries;
    opt.backoff_s = 0.005;
    return opt;
  }

  /// Polls until the pin stops moving (bounded: 5 s real time).
  tocd::devices::TesterReading wait_until_still() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    for (;;) {
      auto r = tester_->read();
      if (!r.status.moving) return r;
      if (std::chrono::steady_clock::now() > deadline) ADD_FAILURE() << "tester never stopped";
      if (std::chrono::steady_clock::now() > deadline) return r;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }

  std::shared_ptr<tocd::mocks::SimClock> clock_;
  std::unique_ptr<tocd::mocks::TesterTwin> twin_;
  std::unique_ptr<tocd::devices::MechanicalTester> tester_;
};
