// Unconfined compression of a cylinder between frictionless plates, drained at its side, at
// finite strain (10 %) with the Holmes-Mow permeability: the water balance holds at every step,
// and after the hold the biphasic solution is the drained hyperelastic one, which for
// frictionless plates is homogeneous uniaxial stress: axial stretch lz, radial stretch lr with
// tau_rr(lr, lr, lz) = 0, force = pi (a lr)^2 tau_zz / J. That reference is computed here with
// a scalar root find on the skeleton law's principal stresses, independently of the FE.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "poro_test_models.hpp"
#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/poro/solver.hpp"

namespace {

using namespace tocd::sim::poro;
namespace mat = tocd::sim::material;

struct DrainedUniaxial {
  double radial_stretch, force_N;
};

DrainedUniaxial drained_uniaxial(const mat::OgdenParameters& p, double lz, double radius) {
  const auto law = mat::make_ogden(p);
  auto tau_rr = [&](double lr) { return law->total(mat::Vec3(lr, lr, lz)).tau[0]; };
  double lo = 0.9, hi = 1.3;  // tau_rr < 0 below the root, > 0 above
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (tau_rr(mid) < 0 ? lo : hi) = mid;
  }
  const double lr = 0.5 * (lo + hi), J = lr * lr * lz;
  const double sigma_zz = law->total(mat::Vec3(lr, lr, lz)).tau[2] / J;
  return {lr, -sigma_zz * std::numbers::pi * std::pow(radius * lr, 2)};
}

TEST(PoroDrainedLimit, WaterBalanceHoldsAndTheHoldEndsDrained) {
  const double mu = 0.01, nu = 0.2, a = 1.0, h = 0.5, strain = 0.1;
  PoroModel m;
  m.kinematics = Kinematics::axisymmetric;
  m.mesh = {a, h, 6, 2, 1.0};
  m.skeleton = reference::skeleton(mu, nu);
  m.permeability = {1.0, 0.2, 1.0, 2.0};
  m.left.fix_x = true;     // axis
  m.bottom.fix_y = true;   // frictionless base
  m.right.drained = true;  // free, drained side
  const double c = m.permeability.k0_mm4_per_Ns * reference::constrained_modulus(mu, nu);
  const double t_ramp = 0.1 * a * a / c, t_end = 30 * a * a / c;
  m.plate.enabled = true;
  m.plate.displacement_mm = [=](double t) { return strain * h * std::min(t / t_ramp, 1.0); };
  PoroSolver solver(m);

  double worst_balance = 0, peak_force = 0;
  const int ramp_steps = 10, hold_steps = 40;
  for (int n = 1; n <= ramp_steps + hold_steps; ++n) {
    const double t = n <= ramp_steps ? t_ramp * n / ramp_steps
                                     : t_ramp * std::pow(t_end / t_ramp, double(n - ramp_steps) / hold_steps);
    const auto& s = solver.advance_to(t);
    peak_force = std::max(peak_force, s.plate_force_N);
    // Water that left + water still held - 0 at t = 0: the consistent Darcy reactions close
    // the balance to the Newton tolerance (energy norm 1e-20: residuals ~1e-10 relative).
    worst_balance = std::max(worst_balance, std::abs(s.water_outflow_mm3 + s.water_content_change_mm3) /
                                                std::abs(s.water_content_change_mm3));
  }
  const auto& s = solver.state();
  EXPECT_GT(s.water_outflow_mm3, 0);  // compression drives water out
  EXPECT_LT(worst_balance, 1e-6);

  const auto drained = drained_uniaxial(m.skeleton, 1 - strain, a);
  // The relaxation: during the ramp the pressurised water stiffens the response. Its upper
  // bound is the undrained (isochoric) one, Young's modulus 3 mu against the drained
  // 2 mu (1 + nu): a ratio 1.25 at nu = 0.2; a ramp over 0.1 consolidation times drains part.
  EXPECT_GT(peak_force, 1.1 * drained.force_N);
  EXPECT_LT(peak_force, 1.25 * 1.05 * drained.force_N);  // 5 %: finite strain at 10 %
  // Residual water pressure after 30 consolidation times is exp(-30 ...) small; the
  // homogeneous field is in the Q2 space, so only that and the Newton tolerance remain.
  EXPECT_NEAR(s.plate_force_N, drained.force_N, 0.01 * drained.force_N);
  for (double y : {0.0, 0.25, 0.5}) {
    const double ur = solver.displacement_at(a, y)[0];
    EXPECT_NEAR(ur, a * (drained.radial_stretch - 1), 0.01 * a * (drained.radial_stretch - 1)) << "y = " << y;
  }
  std::printf(
      "unconfined hold: water balance %.2g relative; force %.5g N vs drained %.5g N (peak %.5g N); "
      "outflow %.4g mm^3\n",
      worst_balance, s.plate_force_N, drained.force_N, peak_force, s.water_outflow_mm3);
}

}  // namespace
