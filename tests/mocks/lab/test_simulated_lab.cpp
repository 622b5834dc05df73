// The simulated lab end to end: open_lab on its config, every instrument on its real wire.
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "tocd/devices/errors.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/mocks/tester_twin.hpp"
#include "tocd/mocks/vacuum_twin.hpp"

using namespace tocd;

namespace {

mocks::SimulatedLabOptions fast() {
  mocks::SimulatedLabOptions o;
  o.clock_factor = 50.0;
  o.source_power_W = 1e-3;
  return o;
}

devices::TesterReading settle(devices::MechanicalTester& t) {
  for (int i = 0; i < 2000; ++i) {
    const auto r = t.read();
    if (!r.status.moving) return r;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ADD_FAILURE() << "the tester never settled";
  return t.read();
}

TEST(SimulatedLab, ConfigOpensEveryInstrument) {
  mocks::SimulatedLab lab(fast());
  const devices::LabConfig cfg = lab.config();
  ASSERT_TRUE(cfg.tester && cfg.power_meter && cfg.vacuum);
  // The config survives its own TOML form (what `tocdlab simlab` prints).
  const devices::LabConfig again = devices::parse_lab_config(devices::to_toml(cfg), "simlab");
  devices::LabInstruments in = devices::open_lab(again);
  ASSERT_TRUE(in.tester && in.power_meter && in.vacuum);
  EXPECT_EQ(in.tester->identity().vendor, "tocdlab");
  EXPECT_FALSE(in.power_meter->identity().model.empty());
  EXPECT_EQ(in.vacuum->identity().model, "simulated pump controller VC-1");
  EXPECT_NEAR(in.vacuum->read().pressure_kPa, 101.3, 0.1);
}

TEST(SimulatedLab, PowerFollowsTransmissionAtThePinDisplacement) {
  mocks::SimulatedLabOptions o = fast();
  o.with_vacuum = false;
  const auto tissue = mocks::make_analytic_tissue(2.5);
  o.tissue = tissue;
  mocks::SimulatedLab lab(o);
  devices::LabInstruments in = devices::open_lab(lab.config());
  ASSERT_FALSE(in.vacuum);
  in.power_meter->zero();  // remove the dark offset
  in.power_meter->set_averaging(100);
  for (const double position : {0.5, 1.5, 2.5}) {  // above contact, 0.5 mm in, 1.5 mm in
    in.tester->move_to(position, 10.0);
    const auto r = settle(*in.tester);
    const double d = std::max(0.0, position - 1.0);
    EXPECT_NEAR(lab.tester().displacement_mm(), d, 1e-6);
    const double expected = 1e-3 * tissue->transmission(d);
    const double got = in.power_meter->measure().power_W;
    // Noise: 0.2 % per sample, averaged over 100 -> 0.02 %; allow 5 sigma + zeroing residue.
    EXPECT_NEAR(got, expected, 1e-3 * expected + 2e-9) << "position " << position;
    if (d > 0) {
      EXPECT_GT(r.load_N, 0.0);
    }
  }
}

// Delayed clearing: 30 % of the change in T waits for the water, which drains with the load's
// relaxation time (20 s). Right after a fast step T sits between the instant and the drained
// value the model gives at the tester's drained displacement; after 8 relaxation times it is
// T(d) to within the noise (the rest, 0.3 e^-8 of the step, is 1e-4 of it).
TEST(SimulatedLab, DelayedClearingLetsTRiseWhileTheWaterDrains) {
  mocks::SimulatedLabOptions o = fast();
  o.clock_factor = 20.0;  // 20 s of drainage per real second
  o.with_vacuum = false;
  o.delayed_clearing = 0.3;
  const auto tissue = mocks::make_analytic_tissue(2.5);
  o.tissue = tissue;
  mocks::SimulatedLab lab(o);
  devices::LabInstruments in = devices::open_lab(lab.config());
  in.power_meter->zero();
  in.power_meter->set_averaging(10);
  auto model = [&](double d, double dd) {
    return 1e-3 * (0.7 * tissue->transmission(d) + 0.3 * tissue->transmission(dd));
  };
  // Noise: 0.2 % per sample, 10 averaged: 0.063 %; 5 sigma.
  auto noise = [](double P) { return 5 * 0.002 / std::sqrt(10.0) * P + 2e-9; };

  in.tester->move_to(2.5, 10.0);  // 1.5 mm into the sample in 0.15 s
  settle(*in.tester);
  const double d = lab.tester().displacement_mm();
  ASSERT_NEAR(d, 1.5, 1e-6);
  const double dd_before = lab.tester().drained_displacement_mm();
  const double early = in.power_meter->measure().power_W;
  const double dd_after = lab.tester().drained_displacement_mm();
  EXPECT_LT(dd_before, 0.5 * d) << "the water has hardly begun to drain";
  EXPECT_LE(dd_before, dd_after);
  EXPECT_GE(early, model(d, dd_before) - noise(early));
  EXPECT_LE(early, model(d, dd_after) + noise(early));
  EXPECT_LT(early, 1e-3 * tissue->transmission(d) - 10 * noise(early)) << "not yet cleared";

  std::this_thread::sleep_for(std::chrono::milliseconds(8000));  // 160 s, 8 relaxation times
  const double dd_late = lab.tester().drained_displacement_mm();
  EXPECT_NEAR(dd_late, d, d * std::exp(-7.0));
  const double late = in.power_meter->measure().power_W;
  EXPECT_NEAR(late, 1e-3 * tissue->transmission(d), noise(late) + 0.3e-3 * std::exp(-7.0));
}

// The truth's time constants reach the tester: with a drainage time of 1 s (the relaxation
// time left at 1000 s), 15 simulated seconds after a step the drained displacement has caught
// up to within e^-14 of it; with the relaxation time's 20 s it would still lag by half.
TEST(SimulatedLab, DrainedDisplacementFollowsTheTruthsTimeConstant) {
  mocks::SampleTruth truth;
  truth.relaxation_time_s = 1000.0;
  truth.delayed_clearing_time_s = 1.0;
  mocks::SimulatedLabOptions o = mocks::simulated_lab_options(truth);
  o.clock_factor = 50.0;
  o.with_vacuum = false;
  EXPECT_EQ(o.delayed_clearing, truth.delayed_clearing);
  mocks::SimulatedLab lab(o);
  devices::LabInstruments in = devices::open_lab(lab.config());
  in.tester->move_to(2.5, 10.0);  // 1.5 mm into the sample in 0.15 s
  settle(*in.tester);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // 15 s simulated, or more
  const double d = lab.tester().displacement_mm();
  ASSERT_NEAR(d, 1.5, 1e-6);
  EXPECT_NEAR(lab.tester().drained_displacement_mm(), d, 1e-4);
}

TEST(SimulatedLab, FaultHooksReachTheirInstruments) {
  mocks::SimulatedLab lab(fast());
  devices::LabInstruments in = devices::open_lab(lab.config());
  in.tester->read();
  lab.drop_tester_connections();
  EXPECT_NO_THROW(in.tester->read());  // reconnects
  lab.trip_load_limit();
  EXPECT_TRUE(in.tester->read().status.limit);
  mocks::ModbusFault f;
  f.kind = mocks::ModbusFaultKind::bad_crc;
  lab.inject_vacuum_fault(f);
  EXPECT_NO_THROW(in.vacuum->read());  // retried
  EXPECT_EQ(lab.vacuum()->faults_pending(), 0);
  ASSERT_TRUE(lab.force_power_over_range(true));
  EXPECT_TRUE(in.power_meter->measure().over_range);
  lab.force_power_over_range(false);
  EXPECT_FALSE(in.power_meter->measure().over_range);
  ASSERT_TRUE(lab.inject_power_meter_error(-222, "Data out of range"));
  EXPECT_THROW(in.power_meter->set_averaging(10), devices::DeviceError);
}

TEST(SimulatedLab, TheTesterEnforcesTheLimitsWrittenToItWhateverItsClientPolls) {
  mocks::SimulatedLab lab(fast());
  devices::LabInstruments in = devices::open_lab(lab.config());
  // A target beyond the travel limit is refused on the wire.
  in.tester->set_limits(3.0, 50.0);
  EXPECT_THROW(in.tester->move_to(3.5, 1.0), devices::DeviceError);
  // A limit lowered under a move already going stops the pin at it, with the travel fault.
  in.tester->move_to(2.9, 1.0);
  in.tester->set_limits(2.0, 50.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // 5 s simulated, unpolled
  const auto r = settle(*in.tester);
  EXPECT_NEAR(r.position_mm, 2.0, 1e-6);
  EXPECT_TRUE(r.status.limit);
  EXPECT_EQ(r.status.fault_code, 2);
  // The load limit stops the pin inside the sample (contact at 1 mm) with the load fault.
  in.tester->clear_fault();
  in.tester->move_to(0.0, 5.0);
  settle(*in.tester);
  in.tester->set_limits(10.0, 1.0);
  in.tester->move_to(2.5, 1.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto l = settle(*in.tester);
  EXPECT_TRUE(l.status.limit);
  EXPECT_EQ(l.status.fault_code, 1);
  EXPECT_GT(l.position_mm, 1.0);
  EXPECT_LT(l.position_mm, 2.5);
  EXPECT_LT(l.load_N, 1.0 + 0.05);
}

TEST(SimulatedLab, ClockFactorMakesTheProtocolFast) {
  mocks::SimulatedLab lab(fast());
  devices::LabInstruments in = devices::open_lab(lab.config());
  const auto t0 = std::chrono::steady_clock::now();
  in.tester->move_to(5.0, 1.0);  // 5 s simulated
  const auto r = settle(*in.tester);
  const double real_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_FALSE(r.status.fault);
  EXPECT_NEAR(r.position_mm, 5.0, 1e-6);
  EXPECT_LT(real_s, 1.0);
}

}  // namespace
