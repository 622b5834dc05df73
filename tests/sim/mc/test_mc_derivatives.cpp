// Perturbation Monte Carlo derivatives of the transmittance (RunSettings::
// transmittance_derivatives): against closed forms and against central finite differences
// of T with common random numbers, per region. Their tallies' reproducibility and the
// switch's neutrality: test_mc_derivative_tallies.cpp.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"

namespace mc = tocd::sim::mc;
namespace msh = tocd::sim::mesh;
using namespace tocd::sim::mc::testing;

namespace {

mc::RunSettings with_derivatives(std::uint64_t photons, std::uint64_t seed, int threads = 2) {
  mc::RunSettings s = settings(photons, seed, threads);
  s.transmittance_derivatives = true;
  s.tally_per_tet = false;
  return s;
}

// Two stacked layers, 20 mm wide (side loss negligible): region 1 on top, region 2 below.
mc::PreparedMesh two_layers(double top_mm, double bottom_mm) {
  msh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 20.0;
  spec.cells_x = spec.cells_y = 4;
  spec.layers = {{top_mm, 1, 2}, {bottom_mm, 2, 2}};
  return mc::prepare(msh::make_slab(spec));
}

// Mean and standard error of per-batch values (batches of equal size, independent).
mc::Estimate batch_mean(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  double m = 0.0;
  for (double v : x) m += v / n;
  double ss = 0.0;
  for (double v : x) ss += (v - m) * (v - m);
  return {m, std::sqrt(ss / (n - 1.0) / n)};
}

// Every batch of a run on its own (run_batches + finish of that one batch): batch b holds the
// same photons, with the same random streams, whatever the optics.
std::vector<mc::Result> per_batch(const mc::PreparedMesh& mesh, const mc::Optics& optics,
                                  const mc::Source& beam, const mc::RunSettings& s) {
  std::vector<mc::Result> out;
  for (int b = 0; b < s.batches; ++b)
    out.push_back(mc::finish(mesh, optics, s, mc::run_batches(mesh, optics, beam, s, b, b + 1)));
  return out;
}

enum class Coefficient { mu_a, mu_s };

// Checks the perturbation estimate of dT/dmu (region `region`, coefficient `which`) against
// the five-point central difference
//   F = (8 (T(mu + h) - T(mu - h)) - (T(mu + 2h) - T(mu - 2h))) / 12h,
// all runs with the same seed (common random numbers: batch b of each run launches the same
// photons with the same streams). The estimates of one batch are correlated, the batches
// independent and identically distributed, so the per-batch differences
//   D_b = perturbation_b - F_b
// have mean (perturbation - finite difference) and a standard error from their spread over
// the batches, SE = sd(D_b) / sqrt(B), which takes the correlations into account. The check
// is |mean D| < 3 SE + 0.2 % of |dT/dmu| for the stencil's truncation error h^4 |T^(5)| / 30:
// T varies with mu_a like a mixture of exp(-mu_a L) over the transmitted paths, so that error
// is about (h L)^4 / 30 relative, below 1e-4 for h <= 0.05 mm^-1 and paths up to 10 mm
// (for mu_s, whose steps are 5-8 % of mu_s, (h / mu_s)^4 / 30 is smaller still). The plain three-point
// difference is not enough here: its (h L)^2 / 6 reaches 1 % at h = 0.03 mm^-1, as Fresnel-trapped light
// travels long paths, and smaller steps drown the difference in noise, which grows as 1/h
// (common random numbers correlate the runs only until the histories part).
void expect_matches_finite_difference(const mc::PreparedMesh& mesh, const mc::Optics& optics,
                                      const mc::Source& beam, std::int32_t region, Coefficient which,
                                      double h, std::uint64_t photons, std::uint64_t seed) {
  mc::RunSettings s = with_derivatives(photons, seed, 1);
  const std::vector<mc::Result> centre = per_batch(mesh, optics, beam, s);
  s.transmittance_derivatives = false;
  auto shifted = [&](double dh) {
    mc::Optics o = optics;
    (which == Coefficient::mu_a ? o.regions[region].mu_a_per_mm : o.regions[region].mu_s_per_mm) += dh;
    return per_batch(mesh, o, beam, s);
  };
  const std::vector<mc::Result> p1 = shifted(h), m1 = shifted(-h), p2 = shifted(2.0 * h),
                                m2 = shifted(-2.0 * h);
  std::vector<double> diff, pert, fd;
  for (std::size_t b = 0; b < centre.size(); ++b) {
    const auto& d = centre[b].transmittance_derivatives.at(region);
    const double p = (which == Coefficient::mu_a ? d.dT_dmu_a : d.dT_dmu_s).mean;
    const double f = (8.0 * (p1[b].transmittance.mean - m1[b].transmittance.mean) -
                      (p2[b].transmittance.mean - m2[b].transmittance.mean)) /
                     (12.0 * h);
    pert.push_back(p);
    fd.push_back(f);
    diff.push_back(p - f);
  }
  const mc::Estimate D = batch_mean(diff), P = batch_mean(pert), F = batch_mean(fd);
  const char* name = which == Coefficient::mu_a ? "mu_a" : "mu_s";
  std::printf(
      "region %d dT/d%s: perturbation %.5f (se %.5f), finite difference %.5f (se %.5f), "
      "difference %.5f (se %.5f)\n",
      region, name, P.mean, P.se, F.mean, F.se, D.mean, D.se);
  EXPECT_GT(D.se, 0.0);
  EXPECT_LT(std::abs(D.mean), 3.0 * D.se + 0.002 * std::abs(P.mean)) << "region " << region << " " << name;
  EXPECT_NE(P.mean, 0.0);
}

}  // namespace

// A ballistic (non-scattering) slab, index-matched: every packet crosses straight down with
// weight exp(-mu_a L), so T = exp(-mu_a L) and dT/dmu_a = -L T with zero variance (only
// round-off in the sum of the tet segments); mu_s does not enter the ballistic model.
TEST(MC_SUITE(McDerivatives), BallisticIndexMatchedSlabIsExact) {
  constexpr double kL = 1.0, kMuA = 0.7;
  const mc::PreparedMesh mesh = slab(20.0, kL, 4, 3);
  const mc::Result r = mc::run(mesh, one_region(props(kMuA, 0.0, 0.0, 1.0)), pencil(0.0, 0.0123, -0.0217, kL),
                               with_derivatives(2000, 3));
  const double T = std::exp(-kMuA * kL);
  EXPECT_NEAR(r.transmittance.mean, T, 1e-12);
  const auto& d = r.transmittance_derivatives.at(1);
  EXPECT_NEAR(d.dT_dmu_a.mean, -kL * T, 1e-12);
  EXPECT_LT(d.dT_dmu_a.se, 1e-12);
  EXPECT_EQ(d.dT_dmu_s.mean, 0.0);
}

// The same slab with n = 1.4 in air: the bottom face reflects a fraction R = ((n-1)/(n+1))^2
// (sampled: the packet goes back up), so light crosses 1, 3, 5 ... times. With x = exp(-mu_a L)
// and the entry's deterministic (1 - R):
//   T = (1 - R)^2 x / (1 - R^2 x^2),  dT/dmu_a = -L x dT/dx,
//   dT/dx = (1 - R)^2 (1 + R^2 x^2) / (1 - R^2 x^2)^2.
// The sampled reflections make it noisy: within 3 standard errors.
TEST(MC_SUITE(McDerivatives), BallisticSlabWithInternalReflectionsMatchesClosedForm) {
  constexpr double kL = 1.0, kMuA = 0.3, kN = 1.4;
  const double R = std::pow((kN - 1.0) / (kN + 1.0), 2.0), x = std::exp(-kMuA * kL);
  const double T = (1 - R) * (1 - R) * x / (1 - R * R * x * x);
  const double dT_dx = (1 - R) * (1 - R) * (1 + R * R * x * x) / std::pow(1 - R * R * x * x, 2.0);
  const double expected = -kL * x * dT_dx;
  const mc::Result r = mc::run(slab(20.0, kL, 4, 3), one_region(props(kMuA, 0.0, 0.0, kN)),
                               pencil(0.0, 0.0123, -0.0217, kL), with_derivatives(200000 * kScale, 5));
  const auto& d = r.transmittance_derivatives.at(1);
  std::printf("T %.6f (closed form %.6f, se %.6f); dT/dmu_a %.6f (closed form %.6f, se %.6f)\n",
              r.transmittance.mean, T, r.transmittance.se, d.dT_dmu_a.mean, expected, d.dT_dmu_a.se);
  EXPECT_GT(d.dT_dmu_a.se, 0.0);
  EXPECT_NEAR(r.transmittance.mean, T, 3.0 * r.transmittance.se);
  EXPECT_NEAR(d.dT_dmu_a.mean, expected, 3.0 * d.dT_dmu_a.se);
}

// Scattering slab (mu_a 0.1, mu_s 10, g 0.9, n 1.4 in air, 1 mm): both derivatives against
// central differences with common random numbers.
TEST(MC_SUITE(McDerivatives), ScatteringSlabMatchesFiniteDifferences) {
  const mc::PreparedMesh mesh = slab(20.0, 1.0, 4, 2);
  const mc::Optics tissue = one_region(props(0.1, 10.0, 0.9, 1.4));
  const mc::Source beam = pencil(0.0, 0.0123, -0.0217, 1.0);
  expect_matches_finite_difference(mesh, tissue, beam, 1, Coefficient::mu_a, 0.03, 120000 * kScale, 17);
  expect_matches_finite_difference(mesh, tissue, beam, 1, Coefficient::mu_s, 0.5, 120000 * kScale, 19);
}

// Two layers with different optics: each region's derivative matches the finite difference
// of that region's coefficient alone (the other region held fixed).
TEST(MC_SUITE(McDerivatives), TwoLayersSeparateTheRegions) {
  const mc::PreparedMesh mesh = two_layers(0.5, 0.5);
  mc::Optics optics;
  optics.regions[1] = props(0.1, 10.0, 0.9, 1.4);
  optics.regions[2] = props(0.5, 4.0, 0.8, 1.4);
  const mc::Source beam = pencil(0.0, 0.0123, -0.0217, 1.0);
  expect_matches_finite_difference(mesh, optics, beam, 1, Coefficient::mu_a, 0.03, 60000 * kScale, 23);
  expect_matches_finite_difference(mesh, optics, beam, 2, Coefficient::mu_a, 0.05, 60000 * kScale, 29);
  expect_matches_finite_difference(mesh, optics, beam, 2, Coefficient::mu_s, 0.3, 60000 * kScale, 31);
}
