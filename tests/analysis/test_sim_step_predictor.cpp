// The adapter from recorded steps to the FE + mesh + Monte Carlo predictor.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace acq = tocd::acquisition;
namespace an = tocd::analysis;

namespace {

an::SimPredictorSettings settings_of(std::uint64_t photons, std::uint64_t seed) {
  an::SimPredictorSettings s;
  s.photons = photons;
  s.seed = seed;
  return s;
}

/// A step predictor over a study predictor of its own (one worker), whose caches a test reads,
/// and a step of a 2 mm sample.
struct Predictors {
  Predictors(std::uint64_t photons, std::uint64_t seed) : steps(study, settings_of(photons, seed)) {
    step.thickness_mm = 2.0;
  }
  std::shared_ptr<tocd::sim::study::Predictor> study = std::make_shared<tocd::sim::study::Predictor>(1);
  an::SimStepPredictor steps;
  acq::RecordedStep step;
};

TEST(SimStepPredictorMath, RatioAndPropagatedError) {
  const auto r = an::relative_to_baseline(0.2, 0.002, 0.4, 0.004);
  EXPECT_DOUBLE_EQ(r.T, 0.5);
  // 1 % relative on each: sqrt(2) % on the ratio.
  EXPECT_NEAR(r.T_stderr, 0.5 * std::sqrt(2.0) * 0.01, 1e-15);
  EXPECT_THROW(an::relative_to_baseline(0.2, 0.002, 0.0, 0.0), tocd::Error);
}

TEST(SimStepPredictor, PredictsRelativeToTheGlassOnlyBaseline) {
  Predictors predictors(6000, 3);
  auto& [study, p, step] = predictors;
  step.displacement_mm = 0.75;
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

// A run's steps are one loading path while the pin goes deeper: each step's FE goes on from the
// step before (its config names the path), a step the pin went back to starts again from first
// touch, and a stored config re-run on a predictor that never saw the run gives the same bits.
TEST(SimStepPredictor, EachStepGoesOnFromThePreviousOneAndItsConfigReproducesIt) {
  Predictors predictors(4000, 5);
  auto& [study, p, step] = predictors;
  p.prepare(step.thickness_mm);  // the glass-only baseline starts before any step
  for (int waited = 0; study->cache_counts().mesh_misses == 0 && waited < 600; ++waited)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(study->cache_counts().mesh_misses, 1u) << "the baseline's mesh, before the first step";

  std::vector<acq::PredictedStep> got;
  for (const double d : {0.0, 0.25, 0.5, 0.75, 0.5}) {
    step.displacement_mm = d;
    got.push_back(p.predict(step).get());
  }
  const auto path_of = [&](std::size_t k) {
    const auto step_config = nlohmann::json::parse(got[k].config_json)["step"];
    return step_config.value("fe_path_mm", std::vector<double>{});
  };
  EXPECT_EQ(path_of(0), std::vector<double>{}) << "no contact, no FE";
  EXPECT_EQ(path_of(1), std::vector<double>{}) << "first touch";
  EXPECT_EQ(path_of(2), (std::vector<double>{0.25}));
  EXPECT_EQ(path_of(3), (std::vector<double>{0.25, 0.5}));
  EXPECT_EQ(path_of(4), std::vector<double>{}) << "the pin went back: from first touch again";
  EXPECT_EQ(study->cache_counts().mesh_misses, 6u) << "one mesh per step and the baseline's";

  // The deepest step's stored config, on a predictor of its own: the same FE along the same
  // path from first touch, the same mesh, the same photons.
  const auto config = nlohmann::json::parse(got[3].config_json);
  tocd::sim::study::Predictor fresh(1);
  const auto again = fresh.predict(tocd::sim::study::request_from_config(config["step"]));
  const auto summary = nlohmann::json::parse(got[3].summary_json);
  EXPECT_EQ(again.T, summary["T_absolute"]["mean"].get<double>());
  ASSERT_TRUE(summary["fe"].contains("force_N")) << summary["fe"];
  EXPECT_EQ(again.fe_summary["force_N"], summary["fe"]["force_N"]);
}

}  // namespace
