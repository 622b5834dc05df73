// The plane-stress thickness stretch (tau_3 = 0 with the in-plane stretches held) against an
// independent solve written here: bisection on the total response's tau_3, which rises with
// x_3 = ln lambda_3 for every stable law. Ogden laws solve it from one exponential per term;
// that solve must give the general one's answer.
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/sim/material/hyperelastic.hpp"

namespace mat = tocd::sim::material;

namespace {

/// lambda_3 with tau_3 = 0, by bisection in x_3 to an interval of 1e-15, within 0.7 of the
/// incompressible guess -(x_1 + x_2) (J from 0.5 to 2: far out, a law's tau_3 need not rise).
double bisected_thickness(const mat::HyperelasticLaw& law, double l1, double l2) {
  auto tau3 = [&](double x3) { return law.total(mat::Vec3(l1, l2, std::exp(x3))).tau[2]; };
  const double guess = -std::log(l1 * l2);
  double lo = guess - 0.7, hi = guess + 0.7;
  EXPECT_LT(tau3(lo), 0);
  EXPECT_GT(tau3(hi), 0);
  while (hi - lo > 1e-15) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;  // no double between them: as close as it gets
    (tau3(mid) < 0 ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

std::vector<std::unique_ptr<mat::HyperelasticLaw>> plane_stress_laws() {
  std::vector<std::unique_ptr<mat::HyperelasticLaw>> v;
  v.push_back(mat::make_ogden(mat::OgdenParameters::published_skin()));
  v.push_back(mat::make_ogden({{0.3, -0.1}, {2.5, -3.0}, {0.5, 0.2}}));  // two volumetric terms
  v.push_back(mat::make_ogden({{0.0023}, {-5.29}, {0.5}}));              // one term, negative alpha
  v.push_back(mat::make_neo_hookean(0.1, 0.4));
  return v;
}

// In-plane stretches of a compressed section: from both stretched to strongly squeezed.
const double kStretches[][2] = {{1.0, 1.0}, {0.6, 1.2}, {1.3, 0.9}, {0.45, 0.5}, {1.5, 1.4}, {0.35, 1.6}};

}  // namespace

TEST(PlaneStress, ThicknessStretchMatchesAnIndependentBisection) {
  for (const auto& law : plane_stress_laws())
    for (const auto& s : kStretches) {
      const double expected = bisected_thickness(*law, s[0], s[1]);
      const double got = law->plane_stress_stretch(s[0], s[1]);
      // The bisection stops within 1e-15 in x_3; Newton's last step was below 1e-13.
      EXPECT_NEAR(std::log(got), std::log(expected), 1e-12)
          << law->describe() << " at " << s[0] << ", " << s[1];
      EXPECT_NEAR(law->total(mat::Vec3(s[0], s[1], got)).tau[2], 0.0, 1e-12 * law->shear_modulus())
          << law->describe();
    }
}

TEST(PlaneStress, OgdenShortcutGivesTheGeneralSolvesAnswer) {
  for (const auto& law : plane_stress_laws()) {
    const auto* ogden = dynamic_cast<const mat::OgdenLaw*>(law.get());
    if (ogden == nullptr) continue;
    for (const auto& s : kStretches) {
      const double general = ogden->HyperelasticLaw::plane_stress_stretch(s[0], s[1]);
      ASSERT_GT(general, 0);
      // The same Newton steps on the same function, evaluated in another order: rounding apart.
      EXPECT_NEAR(ogden->plane_stress_stretch(s[0], s[1]) / general, 1.0, 1e-13) << ogden->describe();
    }
  }
}

TEST(PlaneStress, ANearlyIncompressibleLawFollowsItsIncompressibleLimit) {
  // Bulk modulus K = 10^6 times the shear modulus. tau_3 = tau_3,iso + K J (J - 1) = 0, and
  // tau_3,iso depends on the isochoric stretches only, which differ from the incompressible
  // state's by O(J - 1): so J - 1 = -tau_3,iso(incompressible) / K to second order in
  // tau / K (here below 1e-4, so within 1e-8; the first order term is up to ~1e-5).
  const double mu = 0.2, K = 1e6 * mu;
  const auto law = mat::make_neo_hookean(mu / 2, 2.0 / K);
  for (const auto& s : kStretches) {
    const double incompressible = 1.0 / (s[0] * s[1]);
    const double tau_iso = law->isochoric(mat::Vec3(s[0], s[1], incompressible)).tau[2];
    const double J = law->plane_stress_stretch(s[0], s[1]) * s[0] * s[1];
    EXPECT_NEAR(J - 1.0, -tau_iso / K, 1e-8) << s[0] << ", " << s[1];
  }
}
