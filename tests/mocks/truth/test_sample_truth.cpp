// The sample's truth: draws are reproducible and inside their ranges, validation names the
// field, the default is the default sample (same spec, same cache key), and the clearing
// fractions reach the sample's optics and cache key.
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/core/version.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/test/error_of.hpp"

namespace mocks = tocd::mocks;

namespace {

std::string config_error(const mocks::SampleTruth& t) {
  return tocd::test::error_of<tocd::ConfigError>([&] { mocks::validate(t); });
}

}  // namespace

TEST(SampleTruth, DefaultIsValidAndTheDefaultSample) {
  const mocks::SampleTruth t;
  EXPECT_NO_THROW(mocks::validate(t));
  EXPECT_EQ(t.delayed_clearing, mocks::kDefaultDelayedClearing);
  // The spec with the default truth is the one every entry point prepared before: same key,
  // so the entries already cached stay valid.
  const mocks::SimTissueSpec before = mocks::default_sample_spec(2.0, 1.5);
  const mocks::SimTissueSpec with = mocks::default_sample_spec(2.0, 1.5, {}, t);
  EXPECT_EQ(mocks::sim_tissue_cache_key(before), mocks::sim_tissue_cache_key(with));
  EXPECT_EQ(mocks::sim_tissue_cache_key(with).find("cleared"), std::string::npos);
  EXPECT_EQ(with.stiffness_scale, 1.25);
  // The key of the entries cached before the truth was settable, written out.
  EXPECT_EQ(
      mocks::sim_tissue_cache_key(mocks::default_sample_spec(2.5, 1.5, {}, t)),
      fmt::format("tocdlab simulated sample; format 1; tocdlab {}; thickness_mm 2.5; stiffness_scale 1.25; "
                  "optics_model graded; photons 50000; seed 7; displacements_mm 0.25 0.5 0.75 1 1.25 1.5",
                  tocd::version()));
}

TEST(SampleTruth, DrawIsDeterministicPerSeedAndInsideTheRanges) {
  const mocks::SampleTruthRanges ranges;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const mocks::SampleTruth a = mocks::draw_sample_truth(seed);
    EXPECT_EQ(a, mocks::draw_sample_truth(seed)) << "seed " << seed;
    EXPECT_NE(a, mocks::draw_sample_truth(seed + 1)) << "seed " << seed;
    EXPECT_NO_THROW(mocks::validate(a));
    for (const auto& f : mocks::kSampleTruthFields) {
      const auto& r = ranges.*f.range;
      EXPECT_GE(a.*f.value, r.lo) << f.name << " seed " << seed;
      EXPECT_LE(a.*f.value, r.hi) << f.name << " seed " << seed;
    }
  }
  // The draws cover each range: over 200 seeds the extremes come within 5 % of its ends
  // (a uniform draw misses a 5 % end 200 times with probability 0.95^200 = 3.5e-5).
  for (const auto& f : mocks::kSampleTruthFields) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::uint64_t seed = 0; seed < 200; ++seed) {
      const double v = mocks::draw_sample_truth(seed).*f.value;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    const auto& r = ranges.*f.range;
    EXPECT_LT(lo, r.lo + 0.05 * (r.hi - r.lo)) << f.name;
    EXPECT_GT(hi, r.hi - 0.05 * (r.hi - r.lo)) << f.name;
  }
  // Narrower ranges are honoured, a degenerate one gives its value.
  mocks::SampleTruthRanges narrow;
  narrow.stiffness_scale = {1.5, 1.5};
  EXPECT_EQ(mocks::draw_sample_truth(3, narrow).stiffness_scale, 1.5);
}

TEST(SampleTruth, DrawRefusesRangesBeyondTheLimits) {
  mocks::SampleTruthRanges bad;
  bad.cleared_n_fraction = {1.0, 1.2};  // n 1.656: beyond dry collagen
  EXPECT_THROW(mocks::draw_sample_truth(1, bad), tocd::ConfigError);
  bad = {};
  bad.relaxation_time_s = {30, 10};  // empty
  try {
    mocks::draw_sample_truth(1, bad);
    ADD_FAILURE() << "an empty range was accepted";
  } catch (const tocd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("relaxation_time_s"), std::string::npos) << e.what();
  }
}

TEST(SampleTruth, ValidateRefusesEachFieldOutsideItsLimitsNamingIt) {
  const mocks::SampleTruthRanges limits = mocks::sample_truth_limits();
  for (const auto& f : mocks::kSampleTruthFields) {
    const auto& r = limits.*f.range;
    // The limits themselves are accepted (inclusive).
    for (const double ok : {r.lo, r.hi}) {
      mocks::SampleTruth t;
      t.*f.value = ok;
      EXPECT_EQ(config_error(t), "") << f.name << " = " << ok;
    }
    for (const double bad :
         {r.lo - 1e-9 * std::max(1.0, std::abs(r.lo)), r.hi * (1 + 1e-9) + 1e-12,
          std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      mocks::SampleTruth t;
      t.*f.value = bad;
      const std::string what = config_error(t);
      EXPECT_NE(what.find(f.name), std::string::npos) << f.name << " = " << bad << ": '" << what << "'";
      EXPECT_NE(what.find(fmt::format("{} to {}", r.lo, r.hi)), std::string::npos) << what;
    }
  }
  mocks::SampleTruth t;
  t.cleared_n_fraction = 1.2;
  EXPECT_THROW(mocks::default_sample_spec(2.0, 1.5, {}, t), tocd::ConfigError);
}

TEST(SampleTruth, JsonHasEveryField) {
  const mocks::SampleTruth t = mocks::draw_sample_truth(11);
  const nlohmann::json j = mocks::to_json(t);
  ASSERT_EQ(j.size(), std::size(mocks::kSampleTruthFields));
  for (const auto& f : mocks::kSampleTruthFields) EXPECT_EQ(j.at(f.name).get<double>(), t.*f.value) << f.name;
}

TEST(SampleTruth, LabOptionsCarryTheTimeBehaviour) {
  mocks::SampleTruth t;
  t.relaxation_fraction = 0.2;
  t.relaxation_time_s = 11;
  t.delayed_clearing = 0.45;
  t.delayed_clearing_time_s = 33;
  const mocks::SimulatedLabOptions o = mocks::simulated_lab_options(t);
  EXPECT_EQ(o.relaxation_fraction, 0.2);
  EXPECT_EQ(o.relaxation_time_s, 11);
  EXPECT_EQ(o.delayed_clearing, 0.45);
  EXPECT_EQ(o.delayed_clearing_time_s, 33);
  EXPECT_FALSE(o.tissue);
  // The defaults of the options are the default truth's, but for delayed clearing (0: the
  // analytic stand-in clears at once unless asked).
  const mocks::SimulatedLabOptions plain;
  const mocks::SampleTruth d;
  EXPECT_EQ(plain.relaxation_fraction, d.relaxation_fraction);
  EXPECT_EQ(plain.relaxation_time_s, d.relaxation_time_s);
  EXPECT_EQ(plain.delayed_clearing_time_s, d.delayed_clearing_time_s);
}

// The truth's stiffness and clearing reach the spec; the clearing fractions reach its optics
// (native skin 0.089 / 28.9 mm^-1, g 0.926, n 1.38 times them) and its cache key.
TEST(SimTissueSpecTruth, ClearingFractionsChangeTheOpticsAndTheKey) {
  const mocks::SimTissueSpec published;
  const mocks::SimTissueOptics c = mocks::sim_tissue_cleared_optics(published);
  // Bit for bit the published cleared state (sim/study: simulation 11).
  EXPECT_EQ(c.mu_a_per_mm, 0.0534);
  EXPECT_EQ(c.mu_s_per_mm, 17.34);
  EXPECT_EQ(c.g, 0.926);
  EXPECT_EQ(c.n, 1.518);

  mocks::SampleTruth t;
  t.stiffness_scale = 0.8;
  t.cleared_mu_a_fraction = 0.5;
  t.cleared_mu_s_fraction = 0.7;
  t.cleared_n_fraction = 1.05;
  t.full_clearing_strain = 0.4;
  const mocks::SimTissueSpec s = mocks::default_sample_spec(2.0, 1.5, {}, t);
  EXPECT_EQ(s.stiffness_scale, 0.8);
  EXPECT_EQ(s.full_clearing_strain, 0.4);
  const mocks::SimTissueOptics o = mocks::sim_tissue_cleared_optics(s);
  EXPECT_NEAR(o.mu_a_per_mm, 0.5 * 0.089, 1e-15);
  EXPECT_NEAR(o.mu_s_per_mm, 0.7 * 28.9, 1e-13);
  EXPECT_NEAR(o.n, 1.05 * 1.38, 1e-15);
  EXPECT_EQ(o.g, 0.926);

  const std::string key = mocks::sim_tissue_cache_key(published);
  for (auto change : {+[](mocks::SimTissueSpec& x) { x.cleared_mu_a_fraction = 0.5; },
                      +[](mocks::SimTissueSpec& x) { x.cleared_mu_s_fraction = 0.7; },
                      +[](mocks::SimTissueSpec& x) { x.cleared_n_fraction = 1.05; },
                      +[](mocks::SimTissueSpec& x) { x.full_clearing_strain = 0.4; }}) {
    mocks::SimTissueSpec changed = published;
    change(changed);
    EXPECT_NE(mocks::sim_tissue_cache_key(changed), key);
    EXPECT_NE(mocks::sim_tissue_cache_file("/c", changed), mocks::sim_tissue_cache_file("/c", published));
  }
}
