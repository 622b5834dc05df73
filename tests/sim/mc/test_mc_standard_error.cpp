// A run's standard error, from the spread of its batch means, against the spread of the
// transmittance itself over independent seeds: the errors every fit and interval of the
// project weighs the Monte Carlo by (the optics identification's cost, docs/identify.md).
//
// 200 seeds of 2000 photons each through a scattering slab. The spread of T over the seeds is
// known to about 1 / sqrt(2 * 199) = 5 % of itself, the runs' root-mean-square error far
// better, so their ratio must lie within 20 % of 1 (four of those 5 %). The seeds are fixed, so
// the test is one draw, the same on every run.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

constexpr int kSeeds = 200;
constexpr std::uint64_t kPhotons = 2000;

struct Spread {
  double sd_of_T = 0;   ///< over the seeds
  double rms_se = 0;    ///< the runs' own standard errors
  double sd_of_se = 0;  ///< their scatter, relative to their mean
};

Spread over_seeds(int batches) {
  const mc::PreparedMesh mesh = slab(20.0, 1.0, 5, 3);
  const mc::Optics optics = one_region(props(0.1, 10.0, 0.9, 1.4));
  std::vector<double> t, se;
  for (int s = 1; s <= kSeeds; ++s) {
    mc::RunSettings rs = settings(kPhotons, static_cast<std::uint64_t>(s), 2);
    rs.batches = batches;
    rs.tally_per_tet = false;
    const mc::Result r = mc::run(mesh, optics, pencil(0.0, 0.0123, -0.0217, 1.0), rs);
    t.push_back(r.transmittance.mean);
    se.push_back(r.transmittance.se);
  }
  const auto mean = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m += x;
    return m / static_cast<double>(v.size());
  };
  const auto sd = [&](const std::vector<double>& v) {
    const double m = mean(v);
    double ss = 0;
    for (double x : v) ss += (x - m) * (x - m);
    return std::sqrt(ss / static_cast<double>(v.size() - 1));
  };
  double ms = 0;
  for (double e : se) ms += e * e;
  return {sd(t), std::sqrt(ms / static_cast<double>(se.size())), sd(se) / mean(se)};
}

}  // namespace

TEST(McStandardError, MatchesTheSpreadOfIndependentSeeds) {
  for (const int batches : {20, 100}) {
    const Spread s = over_seeds(batches);
    std::printf(
        "%3d batches: T spread %.6f over %d seeds, rms standard error %.6f (ratio %.3f); "
        "the errors scatter by %.1f %%\n",
        batches, s.sd_of_T, kSeeds, s.rms_se, s.sd_of_T / s.rms_se, 100 * s.sd_of_se);
    EXPECT_NEAR(s.sd_of_T / s.rms_se, 1.0, 0.2) << batches << " batches";
  }
}

TEST(McStandardError, MoreBatchesEstimateItWithLessScatter) {
  // The variance from B batch means is a chi-square draw with B - 1 degrees of freedom, so the
  // error scatters by about 1 / sqrt(2 (B - 1)) of itself: 16 % from 20 batches, 7 % from 100
  // (more where a batch's photons are few and their weights skewed). The optics identification
  // runs 100 for that reason (identify_optics.cpp).
  const Spread twenty = over_seeds(20), hundred = over_seeds(100);
  EXPECT_LT(hundred.sd_of_se, 0.6 * twenty.sd_of_se);
  EXPECT_LT(hundred.sd_of_se, 2.0 / std::sqrt(2.0 * 99));
}
