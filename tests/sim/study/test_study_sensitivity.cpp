// The sensitivity study: batch-wise runs add up to predict()'s answer, common random numbers
// make dT's error small, the FE modelling choices reach the FE, and the JSON is complete.
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/sim/study/sensitivity.hpp"
#include "tocd/test/mc_request.hpp"

namespace st = tocd::sim::study;

TEST(StudySensitivity, CommonRandomNumbersResolveWhatIndependentRunsCannot) {
  st::Predictor predictor;
  // Zero displacement: flat skin, no FE, a cheap mesh.
  st::PredictionRequest base = tocd::test::mc_request(0.0, 20000, 3, 2);
  base.batches = 10;
  st::SensitivityVariant same{"nothing", "same request", base};
  st::SensitivityVariant slide{"slide index", "1.52", base};
  slide.request.slide_n = 1.52;
  st::SensitivityVariant impossible{"pin", "through the skin", base};
  impossible.request.displacement_mm = base.thickness_mm + 1;  // refused before any work
  const auto t = st::run_sensitivity(predictor, base, {same, slide, impossible});
  ASSERT_EQ(t.rows.size(), 2u);
  // A variant that cannot be predicted is listed with its reason, never dropped silently.
  ASSERT_EQ(t.not_computed.size(), 1u);
  EXPECT_EQ(t.not_computed[0].variant.label, "through the skin");
  EXPECT_FALSE(t.not_computed[0].reason.empty());
  EXPECT_NE(st::format_sensitivity(t).find("through the skin   not computed: "), std::string::npos)
      << st::format_sensitivity(t);

  // The batches add up exactly to one predict() of the same request.
  const auto whole = predictor.predict(base);
  EXPECT_EQ(t.T, whole.T);

  // The unchanged request: identical photons, so dT is exactly zero.
  EXPECT_EQ(t.rows[0].dT, 0.0);
  EXPECT_EQ(t.rows[0].dT_se, 0.0);
  EXPECT_FALSE(t.rows[0].resolved);

  // A changed slide index: dT's error from paired batches must be well below the error two
  // independent runs would give (sqrt(2) T_se); a factor 2 is conservative for a change that
  // leaves most photon paths (pin, air, skin) untouched.
  const auto& r = t.rows[1];
  EXPECT_GT(r.dT_se, 0.0);
  EXPECT_LT(r.dT_se, 0.5 * std::hypot(r.T_se, t.T_se));
  EXPECT_NEAR(r.dT, r.T - t.T, 1e-15);

  const auto j = st::to_json(t);
  ASSERT_EQ(j["rows"].size(), 2u);
  ASSERT_EQ(j["tornado"].size(), 2u);
  EXPECT_EQ(j["tornado"][0]["label"], "1.52");  // sorted by |dT|
  EXPECT_EQ(j["rows"][1]["config"]["slide_n"], 1.52);
  ASSERT_EQ(j["not_computed"].size(), 1u);
  EXPECT_EQ(j["not_computed"][0]["factor"], "pin");
  EXPECT_EQ(j["not_computed"][0]["reason"], t.not_computed[0].reason);
}

TEST(StudySensitivity, VariantsChangeOneChoiceEach) {
  st::PredictionRequest base;
  base.displacement_mm = 1.5;
  tocd::sim::material::OgdenParameters stiffer = base.material;
  for (double& m : stiffer.mu) m *= 1.1;
  const auto v = st::sensitivity_variants(base, {{"axis 1 +", stiffer}});
  ASSERT_GE(v.size(), 12u);
  int changed_fields_total = 0;
  for (const auto& s : v) {
    const auto a = st::to_config(base), b = st::to_config(s.request);
    int changed = 0;
    for (auto it = b.begin(); it != b.end(); ++it)
      changed += !a.contains(it.key()) || a[it.key()] != it.value();
    EXPECT_EQ(changed, 1) << s.factor << " = " << s.label;
    changed_fields_total += changed;
  }
  EXPECT_EQ(changed_fields_total, static_cast<int>(v.size()));
  EXPECT_EQ(v.back().request.material.mu, stiffer.mu);
}
