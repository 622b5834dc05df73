// Small indentation against the finite-layer Hertz/Sneddon reference (bonded and sliding).
#include <gtest/gtest.h>

#include "hertz_reference.hpp"
#include "tocd/sim/fe/solve.hpp"

namespace fe = tocd::sim::fe;

namespace {
void check(fe::Bottom bottom, const tocd::sim::material::OgdenParameters& mat, double tol) {
  fe::FeModel m = fe::FeModel::published_default();
  m.material = mat;
  m.bottom = bottom;
  const double h = m.thickness_mm;
  const std::vector<double> d = {0.02 * h, 0.05 * h, 0.1 * h};
  const fe::FeResult r = fe::solve(m, d);
  ASSERT_TRUE(r.complete) << r.stop_reason;
  const double G = mat.initial_shear_modulus(), nu = mat.initial_poisson_ratio(), E = 2 * G * (1 + nu);
  for (const auto& s : r.steps) {
    const double ref =
        layer_sphere_force(E, nu, m.pin_radius_mm, h, s.displacement_mm, bottom == fe::Bottom::bonded);
    EXPECT_NEAR(s.force_N, ref, tol * ref) << fe::to_string(bottom) << " at d = " << s.displacement_mm;
  }
}
}  // namespace

TEST(FeHertz, BondedLayerPublishedSkin) {
  check(fe::Bottom::bonded, tocd::sim::material::OgdenParameters::published_skin(), 0.05);
}
// The not-bonded correction of Dimitriadis et al. is the weaker approximation (its chi^2 term is
// the square of the first-order one); the FE falls below it by 3 % at chi = 0.11 growing to
// 5.3 % at chi = 0.245 (d = 0.1 h) while the bonded case agrees within 2 %. 6 % bounds that.
TEST(FeHertz, SlidingLayerPublishedSkin) {
  check(fe::Bottom::sliding, tocd::sim::material::OgdenParameters::published_skin(), 0.06);
}
