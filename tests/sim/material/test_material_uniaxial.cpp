// Homogeneous uniaxial compression of one axisymmetric element against the closed-form Ogden
// curve (Abaqus form with the D_1 term; lateral stretch from zero lateral stress).
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/sim/fe/element.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace mat = tocd::sim::material;
namespace fe = tocd::sim::fe;

namespace {
// Closed form written independently of the library: W(lz, ll, ll) and its partial derivatives.
struct Closed {
  mat::OgdenParameters p;
  double dW(double lz, double ll, bool wrt_z) const {
    const double J = lz * ll * ll, c = std::cbrt(J);
    double s = 0;
    for (std::size_t i = 0; i < p.mu.size(); ++i) {
      const double a = p.alpha[i], bz = std::pow(lz / c, a), bl = std::pow(ll / c, a);
      // d/dlz and d/dll of (bz + 2 bl) with lb = l J^-1/3.
      s += wrt_z ? 2 * p.mu[i] / a * (bz * (2.0 / 3.0) - 2 * bl / 3.0) / lz
                 : 2 * p.mu[i] / a * (-bz * 2.0 / 3.0 + 2 * bl / 3.0) / ll;
    }
    const double dU = 2 * (J - 1) / p.D[0];
    return s + dU * (wrt_z ? ll * ll : 2 * lz * ll);
  }
  // Lateral stretch with zero lateral stress, then the nominal axial stress.
  double nominal(double lz, double& ll) const {
    ll = 1 / std::sqrt(lz);
    for (int it = 0; it < 100; ++it) {
      const double h = 1e-7 * ll, f = dW(lz, ll, false);
      const double df = (dW(lz, ll + h, false) - dW(lz, ll - h, false)) / (2 * h);
      ll -= f / df;
      if (std::abs(f / df) < 1e-15) break;
    }
    return dW(lz, ll, true);
  }
};
}  // namespace

TEST(MaterialUniaxial, OneAxisymmetricElementMatchesClosedFormOgden) {
  const auto p = mat::OgdenParameters::published_skin();
  const mat::OgdenLaw law(p);
  const Closed cf{p};
  const std::array<std::array<double, 2>, 4> X = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
  const auto ref = fe::make_element_reference(X, fe::Kinematics::axisymmetric);
  for (double lz : {0.95, 0.8, 0.6, 0.4, 0.25}) {
    double ll = 0;
    const double P = cf.nominal(lz, ll);
    std::array<std::array<double, 2>, 4> x;
    for (int a = 0; a < 4; ++a) x[a] = {ll * X[a][0], lz * X[a][1]};
    fe::ElementResponse r;
    ASSERT_TRUE(fe::element_response(ref, x, fe::Kinematics::axisymmetric, law, false, r));
    // Top nodes carry the axial load over the reference area (per radian: int R dR = 1/2).
    const double axial = (r.force[5] + r.force[7]) / 0.5;
    EXPECT_NEAR(axial, P, 1e-6 * std::abs(P)) << "lambda_z = " << lz;
    // The lateral nodes are in equilibrium (zero lateral stress).
    EXPECT_NEAR(r.force[2] + r.force[4], 0, 1e-6 * std::abs(P)) << "lambda_z = " << lz;
  }
}
