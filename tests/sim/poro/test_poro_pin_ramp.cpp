// The pin pushed 1.25 mm into the published 2.5 mm skin with a compressible skeleton (drained
// Poisson's ratio 0.3), ramp 30 s in 10 steps, then a 60 s hold: the case whose Newton
// iteration used to fail a tenth into the ramp ("no admissible Newton step", contact status of
// the axis node flipping between iterations). It converges now; the physics of the hold is
// checked where it could go wrong: water keeps leaving, the pin force relaxes monotonically and
// stays above the drained single-phase FE force it relaxes toward, the water volume balances.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/poro/solver.hpp"

namespace {

using namespace tocd::sim;

// The published FE model with a compressible skeleton: drained Poisson's ratio nu, D_1 = 2 / K.
fe::FeModel drained_fe_model(double nu) {
  fe::FeModel m = fe::FeModel::published_default();
  const double mu = m.material.initial_shear_modulus();
  m.material.D = {3 * (1 - 2 * nu) / (mu * (1 + nu))};
  return m;
}

// Its pin force at depth d; a solve that stops short fails the test with its reason.
double drained_force_N(const fe::FeModel& m, double d) {
  const fe::FeResult r = fe::solve(m, {d});
  if (!r.complete) throw std::runtime_error("drained FE stopped: " + r.stop_reason);
  return r.steps.back().force_N;
}

// Water that left through the drained sides plus the water content change: zero if the
// water volume is conserved.
double water_balance_error(const poro::PoroState& s) {
  return std::abs(s.water_outflow_mm3 + s.water_content_change_mm3);
}

// The ramp to the pin's depth in 10 equal time steps; returns the largest water balance error.
double ramp_in_ten_steps(poro::PoroSolver& solver, double ramp) {
  double worst = 0;
  for (int n = 1; n <= 10; ++n)
    worst = std::max(worst, water_balance_error(solver.advance_to(ramp * n / 10)));
  return worst;
}

// The published skin as a biphasic pin problem (24 x 8 graded mesh, k0 = 1, phi0 = 0.25, top and
// far side drained): the pin to d in `ramp` s, then held.
poro::PoroModel published_pin_model(const fe::FeModel& drained_model, double d, double ramp) {
  poro::PoroModel m;
  m.kinematics = poro::Kinematics::axisymmetric;
  m.mesh = {drained_model.outer_radius_mm, drained_model.thickness_mm, 24, 8, 0.4};
  m.skeleton = drained_model.material;
  m.permeability = {1.0, 0.25, 0.0, 0.0};
  m.left.fix_x = true;
  m.bottom.fix_x = m.bottom.fix_y = true;
  m.top.drained = m.right.drained = true;
  m.pin.enabled = true;
  m.pin.radius_mm = drained_model.pin_radius_mm;
  m.pin.displacement_mm = [=](double t) { return d * std::min(t / ramp, 1.0); };
  return m;
}

// One pin problem of the suite: the pin to d in `ramp` s into a skeleton of drained Poisson's
// ratio nu, beside the drained single-phase FE force at d that its hold relaxes toward.
struct PinRamp {
  PinRamp(double d, double nu, double ramp)
      : drained_model(drained_fe_model(nu)),
        drained_force(drained_force_N(drained_model, d)),
        solver(published_pin_model(drained_model, d, ramp)) {}
  const fe::FeModel drained_model;
  const double drained_force;
  poro::PoroSolver solver;
};

// Smallest volume ratio on a grid of reference points in the top 0.5 mm out to 3 mm.
double smallest_volume_ratio_near_the_pin(const poro::PoroSolver& solver, double thickness_mm) {
  double min_J = 1e9;
  for (double x = 0.005; x < 3.0; x += 0.05)
    for (double y = thickness_mm - 0.5; y < thickness_mm; y += 0.02) {
      const double J = solver.volume_ratio_at(x, y);
      if (std::isfinite(J)) min_J = std::min(min_J, J);
    }
  return min_J;
}

TEST(PoroPinRamp, CompressibleSkeletonThroughTheRampAndAHold) {
  const double d = 1.25, nu = 0.3, ramp = 30, hold = 60;
  PinRamp pin(d, nu, ramp);

  double worst_balance = ramp_in_ten_steps(pin.solver, ramp);
  double force = pin.solver.state().pin_force_N, outflow = pin.solver.state().water_outflow_mm3;
  const double peak = force;
  for (int n = 1; n <= 6; ++n) {
    const auto& s = pin.solver.advance_to(ramp + hold * n / 6);
    worst_balance = std::max(worst_balance, water_balance_error(s));
    // Consolidation under a fixed pin: water leaves, the force relaxes, never below drained.
    EXPECT_GE(s.water_outflow_mm3, outflow) << "t = " << s.time_s;
    EXPECT_LE(s.pin_force_N, force) << "t = " << s.time_s;
    EXPECT_GT(s.pin_force_N, pin.drained_force) << "t = " << s.time_s;
    force = s.pin_force_N;
    outflow = s.water_outflow_mm3;
  }
  const auto& s = pin.solver.state();
  std::printf(
      "pin %.2f mm, nu %.2f, ramp %.0f s: force %.5g N at the end of the ramp, %.5g N after %.0f s (drained "
      "FE "
      "%.5g N); water out %.4g mm^3; balance %.2g mm^3\n",
      d, nu, ramp, peak, s.pin_force_N, hold, pin.drained_force, s.water_outflow_mm3, worst_balance);
  // Over 60 s of a consolidation time h^2 / (k mu) ~ 2900 s the force has relaxed measurably.
  EXPECT_LT(s.pin_force_N, 0.9 * peak);
  EXPECT_LT(worst_balance, 1e-6);
}

// The pin to 1.0 mm in 10 s, then a 60 s hold. It failed 0.04 s into the hold ("no admissible
// Newton step", docs/water.md): the top node on the axis had been released from the contact
// for good, nothing but the axis element held it, and that element compacted to the solid
// volume (J = phi0). The node is now held while its neighbour is in contact, the pore-closure
// term stands behind it, and the physics of a consolidating hold holds: the pin force relaxes
// and stays above the drained single-phase FE force, water leaves, the balance closes, and no
// sampled point has its pores closed.
TEST(PoroPinRamp, OneMillimetreHoldAfterAFastRampKeepsThePoresOpen) {
  const double d = 1.0, nu = 0.3, ramp = 10, hold = 60;
  PinRamp pin(d, nu, ramp);

  double worst_balance = ramp_in_ten_steps(pin.solver, ramp);
  const double peak = pin.solver.state().pin_force_N;
  double force = peak, outflow = pin.solver.state().water_outflow_mm3;
  for (double into_hold : {1.0, 2.0, 4.0, 7.0, 11.0, 20.0, 35.0, hold}) {
    const double t = ramp + into_hold;
    const auto& s = pin.solver.advance_to(t);
    worst_balance = std::max(worst_balance, water_balance_error(s));
    EXPECT_LE(s.pin_force_N, force) << "t = " << t;
    EXPECT_GT(s.pin_force_N, pin.drained_force) << "t = " << t;
    force = s.pin_force_N;
    if (t >= 30) {  // the ramp's inflow has reversed by then (docs/water.md, "State")
      EXPECT_GT(s.water_outflow_mm3, outflow) << "t = " << t;
      outflow = s.water_outflow_mm3;
    }
  }
  const double min_J = smallest_volume_ratio_near_the_pin(pin.solver, pin.drained_model.thickness_mm);
  std::printf(
      "pin %.2f mm, nu %.2f, ramp %.0f s: force %.5g -> %.5g N (drained FE %.5g N), water out %.4g mm^3, "
      "smallest sampled J %.4f (phi0 0.25), balance %.2g mm^3, %d halvings in the last step\n",
      d, nu, ramp, peak, pin.solver.state().pin_force_N, pin.drained_force,
      pin.solver.state().water_outflow_mm3, min_J, worst_balance, pin.solver.state().step_halvings);
  EXPECT_GT(min_J, 0.25);
  EXPECT_LT(pin.solver.state().pin_force_N, 0.95 * peak);
  EXPECT_LT(worst_balance, 1e-6);
}

// 1.25 mm, nu = 0.3, held for about one consolidation time (2900 s, docs/water.md) in the
// three time steps of `predict --times 0,342,1000,3000`: the biphasic pin force tends to the
// drained single-phase FE force. Without the pore-closure term the Gauss point next to the
// axis compacts to the solid volume 372 s into the hold and no time step is admissible; with
// it the hold reaches its end. The term acts only in a small region next to the axis (smallest
// sampled J 0.37, s = 0.16) and the FE has none, so the 1 % bound of the 0.625 mm drained-limit
// test covers it along with the decay still under way at 3000 s and the two discretisations.
TEST(PoroPinRamp, LongHoldAtOnePointTwoFiveMillimetresTendsToTheDrainedForce) {
  const double d = 1.25, nu = 0.3, ramp = 30;
  PinRamp pin(d, nu, ramp);
  ramp_in_ten_steps(pin.solver, ramp);
  double force = pin.solver.state().pin_force_N;
  for (double into_hold : {342.0, 1000.0, 3000.0}) {  // as `predict --times 0,342,1000,3000`
    const auto& s = pin.solver.advance_to(ramp + into_hold);
    EXPECT_LE(s.pin_force_N, force) << into_hold;
    force = s.pin_force_N;
  }
  const double min_J = smallest_volume_ratio_near_the_pin(pin.solver, pin.drained_model.thickness_mm);
  std::printf(
      "pin 1.25 mm, nu 0.3, 3000 s hold: force %.6f N, drained FE %.6f N (%+.2f %%), smallest J %.4f\n",
      force, pin.drained_force, 100 * (force / pin.drained_force - 1), min_J);
  EXPECT_NEAR(force, pin.drained_force, 0.01 * pin.drained_force);
  EXPECT_GT(min_J, 0.25);
}

}  // namespace
