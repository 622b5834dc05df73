// The tester's sample in time, against closed forms: the standard-linear-solid overstress
// after an instantaneous step and after a ramp, and the drained displacement with its own
// time constant.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "tester/tester_physics.hpp"
#include "tocd/mocks/tissue.hpp"

namespace mocks = tocd::mocks;

namespace {

mocks::TesterPhysics::Params quiet_params(std::shared_ptr<mocks::TissueModel> tissue) {
  mocks::TesterPhysics::Params p;
  p.tissue = std::move(tissue);
  p.load_noise_N = 0.0;
  p.load_cell_offset_N = 0.0;
  p.max_load_N = 500.0;
  return p;
}

}  // namespace

// An instantaneous step of equilibrium load dF (the pin covers the whole travel within the
// first 1 ms step), then a hold: the load is dF (1 + g exp(-t/tau)) and the drained
// displacement d (1 - exp(-t/tau_d)), t from the step. Both are exact updates of the model
// (exponential decay over each interval): tolerance 1e-12 relative.
TEST(TesterPhysicsTruth, StepThenHoldRelaxesAsAStandardLinearSolid) {
  const double g = 0.25, tau = 12.0, tau_d = 30.0;
  auto p = quiet_params(mocks::make_analytic_tissue(2.5));
  const auto tissue = p.tissue;
  p.contact_position_mm = 0.0;
  p.relaxation_fraction = g;
  p.relaxation_time_s = tau;
  p.drained_time_s = tau_d;
  p.max_velocity_mm_per_s = 1e4;
  mocks::TesterPhysics physics(p);
  const double d = 1.0;
  ASSERT_EQ(physics.move(d, 1e4), 0);
  physics.advance(1e-3);  // one step: the pin is there
  ASSERT_FALSE(physics.moving());
  ASSERT_EQ(physics.displacement_mm(), d);
  const double dF = tissue->load_N(d);
  ASSERT_GT(dF, 0.01);
  for (const double t : {1e-3, 2.0, 12.0, 40.0, 100.0}) {
    physics.advance(t);
    const double since_step = t - 1e-3;  // the overstress was added at the end of the step
    EXPECT_NEAR(physics.true_load_N(), dF * (1 + g * std::exp(-since_step / tau)), 1e-12 * dF) << "t " << t;
    // The drained displacement drained through the step's 1 ms at the displacement d too.
    EXPECT_NEAR(physics.drained_displacement_mm(), d * (1 - std::exp(-t / tau_d)), 1e-12) << "t " << t;
  }
}

// A ramp at constant speed through a linear equilibrium curve F_eq = k d (a two-point table),
// duration T_r, load dF = k d_end: the overstress at its end is g dF (tau / T_r)(1 - exp(-T_r /
// tau)) (the convolution of the constant load rate with the relaxation), then decays with tau.
// The model adds each 1 ms step's load at its end: the sum differs from the integral by
// O(h / tau) = 1e-4 relative, and the ramp ends within a step of T_r; tolerance 1e-3 of the
// overstress.
TEST(TesterPhysicsTruth, RampGivesTheConvolvedOverstress) {
  const double g = 0.4, tau = 15.0, k = 2.0, d_end = 1.0, v = 0.05;  // T_r = 20 s
  auto p = quiet_params(mocks::make_tabulated_tissue({0.0, 2.0}, {0.0, 2.0 * k}, {1.0, 1.0}));
  p.contact_position_mm = 0.0;
  p.relaxation_fraction = g;
  p.relaxation_time_s = tau;
  p.drained_time_s = 5.0;
  mocks::TesterPhysics physics(p);
  ASSERT_EQ(physics.move(d_end, v), 0);
  double t = 0;
  while (physics.moving() && t < 100) physics.advance(t += 1e-3);
  ASSERT_FALSE(physics.moving());
  const double T_r = d_end / v, dF = k * d_end;
  ASSERT_NEAR(t, T_r, 2e-3);
  const double at_end = g * dF * (tau / T_r) * (1 - std::exp(-T_r / tau));
  // Drainage through the ramp (tau_d = 5 s): dd lags d by v tau_d (1 - exp(-T_r / tau_d)) at its
  // end, and the lag closes with tau_d. The model drains each step towards its final
  // displacement: 1e-4 mm covers it (v h / 2 = 2.5e-5 mm).
  const double tau_d = 5.0;
  const double lag_end = v * tau_d * (1 - std::exp(-T_r / tau_d));
  const double t_end = t;
  for (const double hold : {0.0, 5.0, 10.0, 30.0}) {
    physics.advance(t_end + hold);
    const double overstress = physics.true_load_N() - k * physics.displacement_mm();
    const double expected = at_end * std::exp(-hold / tau);
    EXPECT_NEAR(overstress, expected, 1e-3 * expected) << "hold " << hold;
    EXPECT_NEAR(d_end - physics.drained_displacement_mm(), lag_end * std::exp(-hold / tau_d), 1e-4)
        << "hold " << hold;
  }
}

// The drained displacement follows its own time constant, the overstress the relaxation time:
// the same step with a tenfold tau_d leaves the load unchanged.
TEST(TesterPhysicsTruth, DrainageAndRelaxationHaveSeparateTimeConstants) {
  std::vector<double> loads, drained;
  for (const double tau_d : {4.0, 40.0}) {
    auto p = quiet_params(mocks::make_analytic_tissue(2.5));
    p.contact_position_mm = 0.0;
    p.relaxation_time_s = 20.0;
    p.drained_time_s = tau_d;
    p.max_velocity_mm_per_s = 1e4;
    mocks::TesterPhysics physics(p);
    ASSERT_EQ(physics.move(0.8, 1e4), 0);
    physics.advance(10.0);
    loads.push_back(physics.true_load_N());
    drained.push_back(physics.drained_displacement_mm());
    EXPECT_NEAR(drained.back(), 0.8 * (1 - std::exp(-10.0 / tau_d)), 1e-12);
  }
  EXPECT_EQ(loads[0], loads[1]);
  EXPECT_GT(drained[0], drained[1]);
}
