// The Predictor's contract: caches make a repeated step cheap and identical, configs
// reproduce results, submit() does not block its caller.
#include <chrono>
#include <future>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/test/mc_request.hpp"

namespace st = tocd::sim::study;

namespace {
st::PredictionRequest small(double d_mm) {
  return tocd::test::mc_request(d_mm, 4000, 5, 1);
}
}  // namespace

TEST(StudyPredictor, RepeatedStepHitsTheCachesAndGivesTheSameAnswer) {
  st::Predictor predictor;
  const auto first = predictor.predict(small(1.0));
  EXPECT_FALSE(first.fe_cached);
  EXPECT_FALSE(first.mesh_cached);
  const auto counts = predictor.cache_counts();
  const auto second = predictor.predict(small(1.0));
  EXPECT_TRUE(second.fe_cached);
  EXPECT_TRUE(second.mesh_cached);
  EXPECT_EQ(predictor.cache_counts().fe_misses, counts.fe_misses);
  EXPECT_EQ(predictor.cache_counts().mesh_misses, counts.mesh_misses);
  EXPECT_EQ(second.T, first.T);  // bitwise: same config and seed
  EXPECT_EQ(second.T_stderr, first.T_stderr);
  EXPECT_EQ(second.config, first.config);
  std::printf("first: FE %.3f s, mesh %.3f s; repeated: FE %.6f s, mesh %.6f s\n", first.fe_seconds,
              first.mesh_seconds, second.fe_seconds, second.mesh_seconds);
  // Other optics, same step: FE and mesh reused.
  auto graded = small(1.0);
  graded.optics_model = "graded";
  const auto g = predictor.predict(graded);
  EXPECT_TRUE(g.fe_cached);
  EXPECT_TRUE(g.mesh_cached);
  EXPECT_NE(g.T, first.T);
}

TEST(StudyPredictor, ConfigReproducesThePrediction) {
  st::Predictor a;
  auto r = small(0.7);
  r.thickness_mm = 1.8;
  r.optics_model = "graded";
  const auto p = a.predict(r);
  st::Predictor b;  // fresh caches: everything recomputed from the config alone
  const auto q = b.predict(st::request_from_config(p.config));
  EXPECT_EQ(q.T, p.T);
  EXPECT_EQ(q.side_loss, p.side_loss);
  EXPECT_EQ(q.tets, p.tets);
  EXPECT_EQ(q.config, p.config);
}

TEST(StudyPredictor, SubmitRunsInTheBackground) {
  st::Predictor predictor(1);
  auto f1 = predictor.submit(small(0.9));
  auto f2 = predictor.submit(small(0.9));
  // Returned at once: the FE solve and meshing behind it take far longer than this check.
  EXPECT_EQ(f1.wait_for(std::chrono::seconds(0)), std::future_status::timeout);
  const auto p1 = f1.get();
  const auto p2 = f2.get();
  EXPECT_EQ(p1.T, p2.T);
  EXPECT_TRUE(p2.fe_cached);
  EXPECT_EQ(predictor.predict(small(0.9)).T, p1.T);
  // Errors travel through the future.
  auto bad = small(0.9);
  bad.displacement_mm = 5.0;
  auto f3 = predictor.submit(bad);
  EXPECT_THROW(f3.get(), tocd::ConfigError);
}
