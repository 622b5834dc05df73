// The vacuum controller driver against the Modbus RTU twin on a pseudo-terminal pair.
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "tocd/core/clock.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/devices/vacuum_driver.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/vacuum_twin.hpp"
#include "trickling_rtu_slave.hpp"

using namespace tocd::devices;
using tocd::mocks::ModbusFault;
using tocd::mocks::ModbusFaultKind;

namespace {

class VacuumTest : public ::testing::Test {
 protected:
  static constexpr double kClockFactor = 100.0;

  void SetUp() override {
    clock_ = std::make_shared<tocd::mocks::SimClock>(kClockFactor);
    opt_.clock = clock_;
    twin_ = std::make_unique<tocd::mocks::VacuumTwin>(opt_);
    vacuum_ = connect_modbus_rtu_vacuum(twin_->address(), options());
  }

  ModbusOptions options(int retries = 2) const {
    ModbusOptions o;
    o.timeout_s = 0.2;
    o.retries = retries;
    o.backoff_s = 0.005;
    return o;
  }

  static ModbusFault fault(ModbusFaultKind k, int count = 1) {
    ModbusFault f;
    f.kind = k;
    f.count = count;
    return f;
  }

  /// Simulated seconds until the predicate holds (bounded by `limit_s` simulated).
  template <class Pred>
  VacuumReading wait_for(Pred pred, double limit_s) {
    const auto t0 = clock_->now_ns();
    for (;;) {
      const VacuumReading r = vacuum_->read();
      if (pred(r) || (clock_->now_ns() - t0) * 1e-9 > limit_s) return r;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  tocd::mocks::VacuumTwinOptions opt_;
  std::shared_ptr<tocd::mocks::SimClock> clock_;
  std::unique_ptr<tocd::mocks::VacuumTwin> twin_;
  std::unique_ptr<VacuumController> vacuum_;
};

TEST_F(VacuumTest, IdentityOverThePty) {
  EXPECT_EQ(twin_->device_path().rfind("/dev/pts/", 0), 0u) << twin_->device_path();
  const Identity id = vacuum_->identity();
  EXPECT_EQ(id.vendor, "tocdlab");
  EXPECT_EQ(id.model, "simulated pump controller VC-1");
  EXPECT_EQ(id.serial, "SIMVAC01");
}

TEST_F(VacuumTest, StartsAtAtmosphereWithThePumpOff) {
  const VacuumReading r = vacuum_->read();
  EXPECT_NEAR(r.pressure_kPa, 101.3, 1e-3);
  EXPECT_FALSE(r.pump_running);
  EXPECT_FALSE(r.vent_open);
  EXPECT_EQ(r.error_code, 0);
  EXPECT_NEAR(r.setpoint_kPa, 5.0, 1e-6);
}

TEST_F(VacuumTest, PumpDownFollowsTheFirstOrderLaw) {
  vacuum_->set_setpoint_kPa(2.0);
  const auto before_cmd = clock_->now_ns();
  vacuum_->run_pump(true);
  const auto after_cmd = clock_->now_ns();
  std::this_thread::sleep_for(std::chrono::milliseconds(40));  // ~4 s simulated = one time constant
  const auto before_read = clock_->now_ns();
  const VacuumReading r = vacuum_->read();
  const auto after_read = clock_->now_ns();
  EXPECT_TRUE(r.pump_running);
  // p(t) = p_eq + (p0 - p_eq) exp(-t/tau), p_eq = p_ult + leak tau. The twin started pumping
  // and sampled within known clock brackets, so the pressure lies between the law's values at
  // the shortest and the longest possible pumping time (10 ms steps: +-0.01 s).
  const double p_eq = 0.5 + 0.05 * 4.0;
  auto p_at = [&](double s) { return p_eq + (101.3 - p_eq) * std::exp(-s / 4.0); };
  const double shortest = (before_read - after_cmd) * 1e-9 - 0.01;
  const double longest = (after_read - before_cmd) * 1e-9 + 0.01;
  EXPECT_LE(r.pressure_kPa, p_at(shortest) + 1e-3);
  EXPECT_GE(r.pressure_kPa, p_at(longest) - 1e-3);
  EXPECT_LT(r.pressure_kPa, 101.3 * 0.8);
  const VacuumReading low = wait_for([](const VacuumReading& v) { return v.pressure_kPa <= 3.0; }, 60.0);
  EXPECT_LE(low.pressure_kPa, 3.0);
  EXPECT_GE(low.pressure_kPa, 1.9);  // the controller regulates at the setpoint, not below it
  EXPECT_EQ(low.error_code, 0);
}

TEST_F(VacuumTest, VentReturnsToAtmosphereAndStopHoldsWithTheLeak) {
  vacuum_->set_setpoint_kPa(10.0);
  vacuum_->run_pump(true);
  wait_for([](const VacuumReading& v) { return v.pressure_kPa <= 11.0; }, 60.0);
  vacuum_->run_pump(false);
  const double p1 = vacuum_->read().pressure_kPa;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const VacuumReading held = vacuum_->read();
  EXPECT_FALSE(held.pump_running);
  EXPECT_GT(held.pressure_kPa, p1);                // the leak lets air in
  EXPECT_LT(held.pressure_kPa, p1 + 0.05 * 20.0);  // at 0.05 kPa/s
  vacuum_->set_vent(true);
  const VacuumReading vented = wait_for([](const VacuumReading& v) { return v.pressure_kPa > 100.0; }, 20.0);
  EXPECT_TRUE(vented.vent_open);
  EXPECT_GT(vented.pressure_kPa, 100.0);
}

TEST_F(VacuumTest, SealLossRaisesTheSetpointErrorAndStoppingClearsIt) {
  twin_->inject_seal_loss();
  vacuum_->set_setpoint_kPa(5.0);
  vacuum_->run_pump(true);
  const VacuumReading r = wait_for([](const VacuumReading& v) { return v.error_code != 0; }, 120.0);
  EXPECT_EQ(r.error_code, 1);
  EXPECT_FALSE(r.pump_running);
  EXPECT_THROW(vacuum_->run_pump(true), InstrumentFault);  // refused while in error
  vacuum_->run_pump(false);
  EXPECT_EQ(vacuum_->read().error_code, 0);
  twin_->inject_seal_loss(false);
  vacuum_->run_pump(true);
  EXPECT_TRUE(vacuum_->read().pump_running);
}

TEST_F(VacuumTest, BadSetpointsAreRefused) {
  EXPECT_THROW(vacuum_->set_setpoint_kPa(std::nan("")), tocd::ConfigError);
  EXPECT_THROW(vacuum_->set_setpoint_kPa(-3.0), tocd::ConfigError);
  try {
    vacuum_->set_setpoint_kPa(500.0);  // above atmosphere: the controller says no
    FAIL() << "accepted";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("illegal data value"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(setpoint)"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(vacuum_->read().setpoint_kPa, 5.0, 1e-6);
}

TEST_F(VacuumTest, RetriesAbsorbEachSerialFault) {
  for (auto k : {ModbusFaultKind::bad_crc, ModbusFaultKind::wrong_slave, ModbusFaultKind::garbage,
                 ModbusFaultKind::no_reply, ModbusFaultKind::truncated_frame, ModbusFaultKind::short_frame}) {
    twin_->inject(fault(k));
    EXPECT_NO_THROW(vacuum_->read()) << static_cast<int>(k);
    EXPECT_EQ(twin_->faults_pending(), 0);
  }
}

TEST_F(VacuumTest, EachSerialFaultIsATypedErrorWithoutRetries) {
  vacuum_.reset();
  vacuum_ = connect_modbus_rtu_vacuum(twin_->address(), options(0));
  for (auto k : {ModbusFaultKind::bad_crc, ModbusFaultKind::wrong_slave, ModbusFaultKind::short_frame,
                 ModbusFaultKind::nan_value}) {
    twin_->inject(fault(k));
    EXPECT_THROW(vacuum_->read(), ProtocolError) << static_cast<int>(k);
    EXPECT_NO_THROW(vacuum_->read()) << static_cast<int>(k);
  }
  for (auto k : {ModbusFaultKind::no_reply, ModbusFaultKind::truncated_frame}) {
    twin_->inject(fault(k));
    EXPECT_THROW(vacuum_->read(), TimeoutError) << static_cast<int>(k);
    EXPECT_NO_THROW(vacuum_->read()) << static_cast<int>(k);
  }
  ModbusFault e = fault(ModbusFaultKind::exception);
  e.exception_code = 1;
  twin_->inject(e);
  EXPECT_THROW(vacuum_->read(), ProtocolError);
  EXPECT_NO_THROW(vacuum_->read());
}

TEST_F(VacuumTest, WrongSlaveIdOnOurSideTimesOutBoundedAndTheTwinStaysUsable) {
  ModbusRtuAddress wrong = twin_->address();
  wrong.slave_id = 9;
  vacuum_.reset();
  auto other = connect_modbus_rtu_vacuum(wrong, options(0));
  const auto t0 = tocd::monotonic_ns();
  EXPECT_THROW(other->read(), TimeoutError);  // nobody answers for slave 9
  EXPECT_LT((tocd::monotonic_ns() - t0) * 1e-9, 1.0);
  other.reset();
  vacuum_ = connect_modbus_rtu_vacuum(twin_->address(), options(0));
  EXPECT_NO_THROW(vacuum_->read());
}

TEST_F(VacuumTest, MissingSerialDeviceIsAConnectionError) {
  ModbusRtuAddress a;
  a.device = "/dev/does-not-exist-tocd";
  EXPECT_THROW(connect_modbus_rtu_vacuum(a, options(1)), ConnectionError);
  a.parity = 'X';
  EXPECT_THROW(connect_modbus_rtu_vacuum(a, options(1)), tocd::ConfigError);
}

}  // namespace

TEST(VacuumRtuDeadline, TrickledAnswerFailsAsATimeoutBoundedByTheAnswerLength) {
  // 17 answer bytes (6 registers) at 40 ms each: every gap inside libmodbus's 50 ms byte
  // timeout, the whole answer 0.68 s, past the 0.2 s timeout. libmodbus alone accepts it.
  tocd::devices::testing::TricklingRtuSlave slave(1, std::chrono::milliseconds(40));
  ModbusRtuAddress a;
  a.device = slave.device();
  ModbusOptions o;
  o.timeout_s = 0.2;
  o.retries = 0;
  const auto vacuum = connect_modbus_rtu_vacuum(a, o);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    vacuum->read();
    FAIL() << "a trickled answer was accepted";
  } catch (const TimeoutError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("vacuum controller " + slave.device()), std::string::npos) << msg;
    EXPECT_NE(msg.find("no complete answer within 200 ms"), std::string::npos) << msg;
  }
  // The wait itself is bounded: the answer's 17 bytes at most one byte timeout (50 ms) apart
  // after the 0.2 s response timeout, 1.05 s; plus scheduling slack of a loaded machine.
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(took, 2.0);
}
