// Small indentation (d <= 0.1 h) against the linear-elastic solution for a rigid sphere on a
// finite layer on a rigid base, bonded and sliding (layer_contact_reference.hpp). The FE is
// finite-strain and the material nonlinear, so agreement is expected to a few percent.
#include <gtest/gtest.h>

#include "layer_contact_reference.hpp"
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
  const layer_reference::SphereOnLayer layer(E, nu, m.pin_radius_mm, h, bottom == fe::Bottom::bonded);
  for (const auto& s : r.steps) {
    const double ref = layer.force_at_depth(s.displacement_mm);
    EXPECT_NEAR(s.force_N, ref, tol * ref) << fe::to_string(bottom) << " at d = " << s.displacement_mm;
  }
}
}  // namespace

TEST(FeHertz, BondedLayerPublishedSkin) {
  check(fe::Bottom::bonded, tocd::sim::material::OgdenParameters::published_skin(), 0.05);
}
TEST(FeHertz, SlidingLayerPublishedSkin) {
  check(fe::Bottom::sliding, tocd::sim::material::OgdenParameters::published_skin(), 0.05);
}

// The same initial moduli with the mildest nonlinearity: separates the discretisation from the
// published fit's strain stiffening.
namespace {
// Neo-Hookean (Ogden N = 1, alpha = 2) with the published fit's initial shear and bulk moduli.
tocd::sim::material::OgdenParameters neo_hookean_like_published() {
  const auto p = tocd::sim::material::OgdenParameters::published_skin();
  return {{p.initial_shear_modulus()}, {2.0}, {p.D[0]}};
}
}  // namespace
TEST(FeHertz, BondedLayerNeoHookean) {
  check(fe::Bottom::bonded, neo_hookean_like_published(), 0.05);
}
TEST(FeHertz, SlidingLayerNeoHookean) {
  check(fe::Bottom::sliding, neo_hookean_like_published(), 0.05);
}
