// Non-scattering slabs against closed-form multiple-reflection results, and total internal
// reflection. With mu_s = 0 the only randomness is the Fresnel reflect/transmit choice at
// internal faces, so the tolerance is 4 standard errors of the run (false-alarm rate ~1e-4).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"
#include "tocd/sim/mc/fresnel.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

double fresnel(double n1, double n2, double incidence_deg) {
  double cos_t = 0.0;
  return mc::fresnel_reflectance(n1, n2, std::cos(incidence_deg * std::numbers::pi / 180.0), cos_t);
}

// A slab of index n and absorption mu_a between two half-spaces of index 1, lit at polar
// angle theta0. Inside, the beam runs at theta1 (Snell) over d / cos(theta1) per pass, and
// meets both faces at theta1, where the reflectance equals the entry one R (Fresnel's
// equations are symmetric under reversal). Summing the passes:
//   Tt = (1-R)^2 a / (1 - R^2 a^2),  Rd = (1-R)^2 R a^2 / (1 - R^2 a^2),  a = exp(-mu_a d / cos theta1).
struct Analytic {
  double r, tt, rd;
};
Analytic glass_slab(double n, double mu_a, double d, double theta0_deg) {
  const double th0 = theta0_deg * std::numbers::pi / 180.0;
  const double cos1 = std::sqrt(1.0 - std::pow(std::sin(th0) / n, 2));
  const double r = fresnel(1.0, n, theta0_deg);
  const double a = std::exp(-mu_a * d / cos1);
  const double denom = 1.0 - r * r * a * a;
  return {r, (1 - r) * (1 - r) * a / denom, (1 - r) * (1 - r) * r * a * a / denom};
}

void check_glass(double theta0_deg) {
  constexpr double kN = 1.5, kMuA = 0.5, kD = 1.0;
  const Analytic ref = glass_slab(kN, kMuA, kD, theta0_deg);
  const mc::PreparedMesh mesh = slab(20.0, kD, 5, 3);
  const mc::Result r = mc::run(mesh, one_region(props(kMuA, 0.0, 0.0, kN)),
                               pencil(theta0_deg, 0.0123, -0.0217, kD), settings(500000 * kScale));
  EXPECT_NEAR(r.specular.mean, ref.r, 1e-12);
  EXPECT_NEAR(r.transmittance.mean, ref.tt, 4.0 * r.transmittance.se + 1e-9) << "theta " << theta0_deg;
  EXPECT_NEAR(r.reflectance.mean, ref.rd, 4.0 * r.reflectance.se + 1e-9) << "theta " << theta0_deg;
  EXPECT_GT(r.transmittance.se, 0.0);
  EXPECT_EQ(r.events, 0u);  // ballistic: no scattering events
  EXPECT_NEAR(r.energy_balance_error, 0.0, 1e-9);
  std::printf("glass slab %4.1f deg: Tt %.6f +- %.6f (analytic %.6f), Rd %.6f +- %.6f (analytic %.6f)\n",
              theta0_deg, r.transmittance.mean, r.transmittance.se, ref.tt, r.reflectance.mean,
              r.reflectance.se, ref.rd);
}

// Two layers under an ambient of index 1.5: glass (1.5) on top of a layer of index 1.0, both
// non-absorbing. The glass/low-index interface has critical angle asin(1/1.5) = 41.8 deg.
mc::Result tir_run(double theta_deg) {
  tocd::sim::mesh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 400.0;
  spec.cells_x = spec.cells_y = 4;
  spec.layers = {{1.0, 1, 1}, {1.0, 2, 1}};
  const mc::PreparedMesh mesh = mc::prepare(tocd::sim::mesh::make_slab(spec));
  mc::Optics optics;
  optics.regions[1] = props(0.0, 0.0, 0.0, 1.5);
  optics.regions[2] = props(0.0, 0.0, 0.0, 1.0);
  auto s = settings(100000 * kScale);
  s.ambient_n = 1.5;
  return mc::run(mesh, optics, pencil(theta_deg, 0.0123, -0.0217, 2.0), s);
}

}  // namespace

TEST(MC_SUITE(McAnalytic), GlassSlabNormalIncidence) {
  check_glass(0.0);
}
TEST(MC_SUITE(McAnalytic), GlassSlabObliqueIncidence) {
  check_glass(50.0);
}

TEST(MC_SUITE(McAnalytic), TotalInternalReflectionAboveCriticalAngle) {
  const mc::Result r = tir_run(45.0);
  EXPECT_EQ(r.transmittance.mean, 0.0);
  EXPECT_EQ(r.specular.mean, 0.0);  // matched entry
  EXPECT_NEAR(r.reflectance.mean, 1.0, 1e-12);
}

TEST(MC_SUITE(McAnalytic), PartialTransmissionBelowCriticalAngle) {
  // The low-index layer sits between two index-1.5 media: both its faces reflect R, and
  // with no absorption T = (1-R)^2 / (1-R^2) = (1-R)/(1+R).
  const double r_face = fresnel(1.5, 1.0, 40.0);
  const mc::Result r = tir_run(40.0);
  const double expected = (1.0 - r_face) / (1.0 + r_face);
  EXPECT_NEAR(r.transmittance.mean, expected, 4.0 * r.transmittance.se + 1e-9);
  EXPECT_LT(r.side_loss.mean, 1e-3);
  std::printf("TIR layer at 40 deg: T %.5f +- %.5f (analytic %.5f), side %.1e\n", r.transmittance.mean,
              r.transmittance.se, expected, r.side_loss.mean);
}

TEST(MC_SUITE(McAnalytic), FreePathsAreExponential) {
  // Index-matched slab of thickness d whose scattering barely deflects (g -> 1): a packet
  // crosses it in a straight line and meets N interactions, Poisson with mean mu_t d when the
  // free paths are exponential; implicit capture keeps albedo^N of its weight, so
  //   T = E[albedo^N] = exp(-mu_t d (1 - albedo)) = exp(-mu_a d).
  // A sampler whose mean free path is off by 1 % shifts T by 0.4 %; any other path-length
  // law with the same mean gives a different E[albedo^N]. Deflection lengthens the path by
  // about 1e-5 per interaction, far inside the tolerance.
  constexpr double kMuA = 1.0, kMuS = 9.0, kD = 1.0;
  const mc::PreparedMesh mesh = slab(20.0, kD, 5, 3);
  const mc::Result r = mc::run(mesh, one_region(props(kMuA, kMuS, 0.99999, 1.0)),
                               pencil(0.0, 0.0123, -0.0217, kD), settings(200000 * kScale));
  const double expected = std::exp(-kMuA * kD);
  EXPECT_NEAR(r.transmittance.mean, expected, 4.0 * r.transmittance.se + 1e-4);
  EXPECT_GT(static_cast<double>(r.events) / static_cast<double>(r.photons), 9.0);  // it did scatter
  std::printf("free paths: T %.5f +- %.5f (exp(-mu_a d) %.5f), %.2f events/photon\n", r.transmittance.mean,
              r.transmittance.se, expected, static_cast<double>(r.events) / static_cast<double>(r.photons));
}

TEST(MC_SUITE(Fresnel), NormalIncidenceAndTotalReflection) {
  double cos_t = 0.0;
  EXPECT_NEAR(mc::fresnel_reflectance(1.0, 1.5, 1.0, cos_t), 0.04, 1e-15);
  EXPECT_NEAR(cos_t, 1.0, 1e-15);
  // Brewster angle atan(1.5): p-polarised reflection vanishes, R = Rs / 2.
  const double th_b = std::atan(1.5);
  const double r = mc::fresnel_reflectance(1.0, 1.5, std::cos(th_b), cos_t);
  const double ct = std::cos(std::asin(std::sin(th_b) / 1.5));
  const double rs = (std::cos(th_b) - 1.5 * ct) / (std::cos(th_b) + 1.5 * ct);
  EXPECT_NEAR(r, 0.5 * rs * rs, 1e-14);
  EXPECT_EQ(mc::fresnel_reflectance(1.5, 1.0, std::cos(42.0 * std::numbers::pi / 180.0), cos_t), 1.0);
  EXPECT_LT(mc::fresnel_reflectance(1.5, 1.0, std::cos(41.0 * std::numbers::pi / 180.0), cos_t), 1.0);
  // Grazing incidence reflects everything.
  EXPECT_NEAR(mc::fresnel_reflectance(1.0, 1.5, 1e-9, cos_t), 1.0, 1e-8);
}
