// Transmittance derivatives through the Predictor (PredictionRequest::
// transmittance_derivatives): present per graded region, not part of the config, leave T
// untouched, and agree with a finite difference of the predicted T.
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/sim/study/predictor.hpp"

namespace st = tocd::sim::study;
namespace mc = tocd::sim::mc;

namespace {

// A cheap graded step: 1 mm into 2.5 mm of skin, coarse tets, few photons in 10 batches.
st::PredictionRequest graded_step() {
  st::PredictionRequest r;
  r.displacement_mm = 1.0;
  r.optics_model = "graded";
  r.photons = 40000;
  r.batches = 10;
  r.seed = 9;
  r.max_edge_mm = 0.6;
  r.threads = 2;
  r.transmittance_derivatives = true;
  return r;
}

// One predictor for the tests: the FE solve and the mesh are made once.
st::Predictor& shared_predictor() {
  static st::Predictor predictor;
  return predictor;
}

}  // namespace

TEST(StudyDerivatives, GradedStepHasDerivativesPerRegionAndTheSameT) {
  st::Predictor& predictor = shared_predictor();
  const st::PredictionRequest r = graded_step();
  const st::Prediction with = predictor.predict(r);
  st::PredictionRequest plain = r;
  plain.transmittance_derivatives = false;
  const st::Prediction without = predictor.predict(plain);
  EXPECT_TRUE(without.dT_dmu.empty());
  EXPECT_FALSE(without.mc.contains("transmittance_derivatives"));
  EXPECT_TRUE(with.mc.contains("transmittance_derivatives"));
  // Not part of the config, and no change to the answer or to the caches it uses.
  EXPECT_EQ(with.config, without.config);
  EXPECT_EQ(with.T, without.T);
  EXPECT_EQ(with.T_stderr, without.T_stderr);
  EXPECT_TRUE(without.fe_cached);
  EXPECT_TRUE(without.mesh_cached);
  // Every graded level that holds tets has its region's derivatives (level 0 = region 4).
  const auto levels = with.mesh_stats.at("graded_levels_tets").get<std::vector<std::size_t>>();
  int present = 0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    if (levels[k] == 0) continue;
    const std::int32_t id = k == 0 ? 4 : st::kGradedRegionBase + static_cast<std::int32_t>(k);
    ASSERT_TRUE(with.dT_dmu.count(id)) << "region " << id;
    ++present;
  }
  EXPECT_GE(present, 3);
  // Light crosses the native skin: more absorption there lowers T.
  EXPECT_LT(with.dT_dmu.at(4).dT_dmu_a.mean, 0.0);
}

// The cleared end point's mu_a enters level k's mu_a with weight f_k = k / bins (linear
// interpolation, study_optics.hpp), so dT/d(cleared mu_a) = sum_k (k / bins) dT/dmu_a,k: a
// check of the regions' derivatives through the predictor against the central difference
// (T(+h) - T(-h)) / 2h of its T. All three with the same seed (common random numbers) and
// run batch by batch (Predictor::run_batches + assemble): the per-batch differences
// D_b = perturbation_b - finite difference_b are independent over batches, so their mean
// has the standard error sd(D_b) / sqrt(B), correlations included. Tolerance 3 SE plus 1 % of
// the derivative for the central difference's truncation error: T varies like a mixture of
// exp(-mu_a L) over transmitted paths of a few mm, so with h = 0.04 mm^-1 that error is about
// (h L)^2 / 6 < 0.3 % for L <= 3 mm. (A smaller h would drown the difference in noise, which
// grows as 1/h.)
TEST(StudyDerivatives, FiniteDifferenceThroughThePredictor) {
  st::Predictor& predictor = shared_predictor();
  const st::PredictionRequest r = graded_step();
  const double h = 0.04;  // mm^-1; the cleared mu_a - h stays > 0
  ASSERT_GT(r.graded.cleared.mu_a_per_mm, h);
  auto batch = [&](const st::PredictionRequest& q, int b) {
    return predictor.assemble(q, predictor.run_batches(q, b, b + 1), 0.0);
  };
  st::PredictionRequest up = r, down = r;
  up.transmittance_derivatives = down.transmittance_derivatives = false;
  up.graded.cleared.mu_a_per_mm += h;
  down.graded.cleared.mu_a_per_mm -= h;
  std::vector<double> diff, pert;
  for (int b = 0; b < r.batches; ++b) {
    const st::Prediction c = batch(r, b);
    double p = 0.0;
    for (const auto& [id, d] : c.dT_dmu) {
      if (id <= st::kGradedRegionBase) continue;
      p += static_cast<double>(id - st::kGradedRegionBase) / r.graded.bins * d.dT_dmu_a.mean;
    }
    const double f = (batch(up, b).T - batch(down, b).T) / (2.0 * h);
    pert.push_back(p);
    diff.push_back(p - f);
  }
  auto mean_se = [](const std::vector<double>& x) {
    const double n = static_cast<double>(x.size());
    double m = 0.0, ss = 0.0;
    for (double v : x) m += v / n;
    for (double v : x) ss += (v - m) * (v - m);
    return mc::Estimate{m, std::sqrt(ss / (n - 1.0) / n)};
  };
  const mc::Estimate D = mean_se(diff), P = mean_se(pert);
  std::printf("dT/d(cleared mu_a): perturbation %.5f (se %.5f), minus finite difference %.5f (se %.5f)\n",
              P.mean, P.se, D.mean, D.se);
  EXPECT_NE(P.mean, 0.0);
  EXPECT_GT(D.se, 0.0);
  EXPECT_LT(std::abs(D.mean), 3.0 * D.se + 0.01 * std::abs(P.mean));
}
