// The adapter from recorded steps to the FE + mesh + Monte Carlo predictor.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tocd/analysis/sim_step_predictor.hpp"

namespace acq = tocd::acquisition;
namespace an = tocd::analysis;

namespace {

TEST(SimStepPredictorMath, RatioAndPropagatedError) {
  const auto r = an::relative_to_baseline(0.2, 0.002, 0.4, 0.004);
  EXPECT_DOUBLE_EQ(r.T, 0.5);
  // 1 % relative on each: sqrt(2) % on the ratio.
  EXPECT_NEAR(r.T_stderr, 0.5 * std::sqrt(2.0) * 0.01, 1e-15);
  EXPECT_THROW(an::relative_to_baseline(0.2, 0.002, 0.0, 0.0), tocd::Error);
}

TEST(SimStepPredictor, PredictsRelativeToTheGlassOnlyBaseline) {
  an::SimPredictorSettings s;
  s.photons = 6000;
  s.seed = 3;
  auto study = std::make_shared<tocd::sim::study::Predictor>(1);
  an::SimStepPredictor p(study, s);
  acq::RecordedStep step;
  step.displacement_mm = 0.75;
  step.thickness_mm = 2.0;
  const acq::PredictedStep a = p.predict(step).get();
  const auto cfg = nlohmann::json::parse(a.config_json);
  const auto summary = nlohmann::json::parse(a.summary_json);
  // The stored value is exactly the ratio of the two Monte Carlo estimates in the summary.
  const double T = summary["T_absolute"]["mean"], T0 = summary["T_baseline"]["mean"];
  EXPECT_DOUBLE_EQ(a.T, T / T0);
  EXPECT_GT(a.T_stderr, 0.0);
  EXPECT_LT(a.T_stderr, 0.2 * a.T);
  // Skin transmits less than glass alone.
  EXPECT_GT(a.T, 0.0);
  EXPECT_LT(a.T, 1.0);
  EXPECT_EQ(cfg["step"]["displacement_mm"], 0.75);
  EXPECT_EQ(cfg["step"]["thickness_mm"], 2.0);
  EXPECT_TRUE(cfg["baseline"]["baseline"].get<bool>());
  EXPECT_NE(cfg["step"]["seed"], cfg["baseline"]["seed"]) << "ratio of independent estimates";

  // Same step again: same answer (seeded), served from the FE and mesh caches.
  const auto before = study->cache_counts();
  const acq::PredictedStep b = p.predict(step).get();
  EXPECT_EQ(a.T, b.T);
  EXPECT_EQ(a.T_stderr, b.T_stderr);
  const auto after = study->cache_counts();
  EXPECT_EQ(after.fe_misses, before.fe_misses);
  EXPECT_EQ(after.mesh_misses, before.mesh_misses);

  // A step the model cannot take fails at once, naming the field.
  step.displacement_mm = 2.5;
  EXPECT_THROW(p.predict(step), tocd::ConfigError);
}

}  // namespace
