#pragma once

// A mechanical tester that passes every call to another one: the tests that change one
// behaviour of a real (or fake) driver override just that call.

#include <memory>
#include <utility>

#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition::testing {

class ForwardingTester : public devices::MechanicalTester {
 public:
  explicit ForwardingTester(std::unique_ptr<devices::MechanicalTester> real) : real_(std::move(real)) {}

  const devices::InstrumentCapabilities& describe() const override { return real_->describe(); }
  devices::Identity identity() override { return real_->identity(); }
  devices::TesterReading read() override { return real_->read(); }
  void move_to(double position_mm, double velocity_mm_per_s) override {
    real_->move_to(position_mm, velocity_mm_per_s);
  }
  void stop() override { real_->stop(); }
  void home() override { real_->home(); }
  void tare_load() override { real_->tare_load(); }
  void set_limits(double travel_mm, double load_N) override { real_->set_limits(travel_mm, load_N); }
  void clear_fault() override { real_->clear_fault(); }

 protected:
  devices::MechanicalTester& real() { return *real_; }

 private:
  std::unique_ptr<devices::MechanicalTester> real_;
};

}  // namespace tocd::acquisition::testing
