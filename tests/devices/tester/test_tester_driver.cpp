// Every tester driver operation against the Modbus TCP twin on loopback.
#include <cmath>

#include "tester_fixture.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/test/device_identity.hpp"

using namespace tocd::devices;

TEST_F(TesterTest, IdentityComesFromTheRegisterMap) {
  EXPECT_EQ(tester_->identity(), (Identity{"tocdlab", "simulated load frame LF-1", "SIM00001", "1.0.0"}));
}

TEST_F(TesterTest, StartsReadyAtHomeWithTheLoadCellOffset) {
  const TesterReading r = tester_->read();
  EXPECT_EQ(r.position_mm, 0.0);
  EXPECT_TRUE(r.status.ready);
  EXPECT_FALSE(r.status.moving);
  EXPECT_FALSE(r.status.fault);
  EXPECT_NEAR(r.load_N, 0.05, 1e-6);  // unloaded cell before tare
  EXPECT_GT(r.t_ns, 0);
  tester_->tare_load();
  EXPECT_NEAR(tester_->read().load_N, 0.0, 1e-6);
}

TEST_F(TesterTest, MovesAtFiniteSpeedAndLoadFollowsTheTissue) {
  tester_->tare_load();
  const auto t0 = clock_->now_ns();
  tester_->move_to(2.0, 4.0);  // 1 mm above contact + 1 mm into the sample, at 4 mm/s
  const TesterReading moving = tester_->read();
  EXPECT_TRUE(moving.status.moving);
  const TesterReading r = wait_until_still();
  const double elapsed_s = (clock_->now_ns() - t0) * 1e-9;
  EXPECT_GE(elapsed_s, 0.5 - 0.01);  // 2 mm at 4 mm/s cannot take less than 0.5 s
  EXPECT_NEAR(r.position_mm, 2.0, 1e-6);
  EXPECT_TRUE(r.status.at_target);
  const double equilibrium = tocd::mocks::make_analytic_tissue(2.5)->load_N(1.0);
  EXPECT_GT(r.load_N, equilibrium);  // overstress of the fast move still there
  EXPECT_LT(r.load_N, 1.31 * equilibrium);
}

TEST_F(TesterTest, LoadRelaxesTowardEquilibriumWhileHolding) {
  tester_->tare_load();
  tester_->move_to(2.0, 10.0);
  const double first = wait_until_still().load_N;
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // 30 s simulated, 1.5 time constants
  const double later = tester_->read().load_N;
  const double eq = tocd::mocks::make_analytic_tissue(2.5)->load_N(1.0);
  EXPECT_LT(later, first);
  EXPECT_GT(later, eq);
  // Overstress decays as exp(-t/20 s): after >= 30 s less than exp(-1.5) = 0.22 of it is left.
  EXPECT_LT(later - eq, 0.23 * (first - eq) + 1e-3);
}

TEST_F(TesterTest, StopHaltsAndHomeReturns) {
  tester_->move_to(8.0, 2.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  tester_->stop();
  const TesterReading stopped = tester_->read();
  EXPECT_FALSE(stopped.status.moving);
  EXPECT_GT(stopped.position_mm, 0.0);
  EXPECT_LT(stopped.position_mm, 8.0);
  tester_->home();
  EXPECT_NEAR(wait_until_still().position_mm, 0.0, 1e-9);
}

TEST_F(TesterTest, LoadLimitTripsStopsAndClears) {
  tester_->set_limits(10.0, 1.0);
  tester_->move_to(3.0, 5.0);
  const TesterReading r = wait_until_still();
  EXPECT_TRUE(r.status.limit);
  EXPECT_TRUE(r.status.fault);
  EXPECT_FALSE(r.status.ready);
  EXPECT_EQ(r.status.fault_code, 1);
  EXPECT_LT(r.position_mm, 3.0);
  EXPECT_GT(r.load_N, 0.9);
  EXPECT_THROW(tester_->move_to(2.5, 1.0), InstrumentFault);  // refused until cleared
  tester_->clear_fault();
  tester_->move_to(0.5, 5.0);
  const TesterReading back = wait_until_still();
  EXPECT_FALSE(back.status.fault);
  EXPECT_NEAR(back.position_mm, 0.5, 1e-6);
}

TEST_F(TesterTest, RefusedCommandsAreTypedErrors) {
  try {
    tester_->move_to(50.0, 1.0);  // beyond the 10 mm travel limit
    FAIL() << "no error";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("illegal data value"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("registers 0..4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mechanical tester 127.0.0.1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tester_->move_to(std::nan(""), 1.0), tocd::ConfigError);
  EXPECT_THROW(tester_->move_to(1.0, 0.0), tocd::ConfigError);
  EXPECT_THROW(tester_->set_limits(-1.0, 5.0), tocd::ConfigError);
  EXPECT_FALSE(tester_->read().status.moving);  // nothing started
}

TEST_F(TesterTest, NobodyListeningIsAConnectionErrorWithinTheBound) {
  const int port = twin_->port();
  twin_.reset();
  const auto t0 = tocd::monotonic_ns();
  EXPECT_THROW(connect_modbus_tcp_tester({"127.0.0.1", port, 1}, options(1)), ConnectionError);
  EXPECT_LT((tocd::monotonic_ns() - t0) * 1e-9, 2.0);
}

TEST_F(TesterTest, TwinDisplacementFollowsContact) {
  tester_->move_to(1.5, 10.0);
  wait_until_still();
  EXPECT_NEAR(twin_->position_mm(), 1.5, 1e-6);
  EXPECT_NEAR(twin_->displacement_mm(), 0.5, 1e-6);
}
