// Element diagnostics: internal force vs finite differences of the energy, tangent vs finite
// differences of the force, for every kinematics, including an element on the symmetry axis.
#include <random>

#include <gtest/gtest.h>

#include "tocd/sim/fe/element.hpp"

namespace fe = tocd::sim::fe;
namespace mat = tocd::sim::material;
using Nodes = std::array<std::array<double, 2>, 4>;

namespace {
void check_element(const Nodes& X, fe::Kinematics k, double amplitude, unsigned seed) {
  const mat::OgdenLaw law(mat::OgdenParameters::published_skin());
  const auto ref = fe::make_element_reference(X, k);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Nodes x = X;
  for (auto& p : x) {
    p[0] += u(rng);
    p[1] += u(rng) - 0.2 * amplitude * p[1];
  }
  for (int a = 0; a < 4; ++a)
    if (X[a][0] == 0) x[a][0] = 0;  // nodes on the axis stay there
  fe::ElementResponse r;
  ASSERT_TRUE(fe::element_response(ref, x, k, law, true, r));
  const double h = 1e-7;
  const double fscale = r.force.norm(), kscale = r.stiffness.norm();
  for (int d = 0; d < 8; ++d) {
    if (X[d / 2][0] == 0 && d % 2 == 0) continue;
    Nodes xp = x, xm = x;
    xp[d / 2][d % 2] += h;
    xm[d / 2][d % 2] -= h;
    fe::ElementResponse rp, rm;
    ASSERT_TRUE(fe::element_response(ref, xp, k, law, false, rp));
    ASSERT_TRUE(fe::element_response(ref, xm, k, law, false, rm));
    EXPECT_NEAR(r.force[d], (rp.energy - rm.energy) / (2 * h), 1e-6 * fscale) << "dof " << d;
    const fe::ElementVector col = (rp.force - rm.force) / (2 * h);
    for (int e = 0; e < 8; ++e) {
      if (X[e / 2][0] == 0 && e % 2 == 0) continue;
      EXPECT_NEAR(r.stiffness(e, d), col[e], 1e-6 * kscale) << "K(" << e << "," << d << ")";
    }
  }
  EXPECT_LT((r.stiffness - r.stiffness.transpose()).norm(), 1e-12 * kscale);
}
}  // namespace

TEST(FeElement, AxisymmetricOffAxis) {
  check_element({{{0.5, 0.0}, {0.8, 0.0}, {0.8, 0.3}, {0.5, 0.3}}}, fe::Kinematics::axisymmetric, 0.05, 1);
  check_element({{{0.5, 0.0}, {0.8, 0.0}, {0.8, 0.3}, {0.5, 0.3}}}, fe::Kinematics::axisymmetric, 0.1, 2);
}

TEST(FeElement, AxisymmetricOnAxis) {
  check_element({{{0.0, 1.0}, {0.1, 1.0}, {0.1, 1.2}, {0.0, 1.2}}}, fe::Kinematics::axisymmetric, 0.02, 3);
}

TEST(FeElement, PlaneStrainAndPlaneStress) {
  const Nodes X = {{{0.5, 0.0}, {0.8, 0.0}, {0.8, 0.3}, {0.5, 0.3}}};
  check_element(X, fe::Kinematics::plane_strain, 0.08, 4);
  check_element(X, fe::Kinematics::plane_stress, 0.08, 5);
}

TEST(FeElement, InvertedElementIsRejected) {
  const mat::OgdenLaw law(mat::OgdenParameters::published_skin());
  const Nodes X = {{{0.5, 0.0}, {0.8, 0.0}, {0.8, 0.3}, {0.5, 0.3}}};
  const auto ref = fe::make_element_reference(X, fe::Kinematics::axisymmetric);
  Nodes x = X;
  x[2][1] = -0.1;  // top-right node pushed below the bottom edge
  x[3][1] = -0.1;
  fe::ElementResponse r;
  EXPECT_FALSE(fe::element_response(ref, x, fe::Kinematics::axisymmetric, law, true, r));
}
