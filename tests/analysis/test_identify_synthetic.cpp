// Identification against runs written in closed form (synthetic_run.hpp), whose truth is known
// exactly: the estimates land on the truth, the 95 % intervals cover it as often as they say,
// and what the run cannot tell is reported as such.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "synthetic_run.hpp"
#include "tocd/analysis/identify_clearing.hpp"
#include "tocd/analysis/identify_mechanics.hpp"
#include "tocd/core/error.hpp"

namespace a = tocd::analysis;
using a::testing::covers;
using a::testing::make_synthetic_run;
using a::testing::SyntheticTruth;

namespace {

a::MechanicsIdentification mechanics_of(const a::testing::SyntheticRun& run, int terms = 1) {
  a::MechanicsOptions o;
  o.prony_terms = terms;
  return a::identify_mechanics(run.history, run.knots_mm, run.elastic_N, o);
}

}  // namespace

TEST(IdentifyMechanics, RecoversTheQlvOfAClosedFormRun) {
  const SyntheticTruth truth;
  const auto m = mechanics_of(make_synthetic_run(truth, 1));
  const auto& r = m.report;
  EXPECT_TRUE(r.converged);
  for (const auto& [name, value] :
       {std::pair{"stiffness_scale", truth.scale}, {"g1", truth.g}, {"tau1_s", truth.tau_s}}) {
    const auto& p = r.at(name);
    EXPECT_TRUE(p.determined) << name << ": " << p.why_not;
    EXPECT_TRUE(covers(p, value)) << name << " " << p.value << " [" << p.lo << ", " << p.hi << "] truth "
                                  << value;
    // The estimate is within 4 standard errors (a miss beyond that has probability 6e-5).
    EXPECT_LT(std::abs(p.value - value), 4 * p.se) << name;
  }
  // The noise the intervals rest on is the noise put in (15,000 readings: 1 % precision).
  EXPECT_NEAR(r.noise_sigma, truth.load_noise_N, 0.05 * truth.load_noise_N);
  EXPECT_LT(std::abs(r.autocorrelation), 0.05);
}

TEST(IdentifyMechanics, NinetyFivePercentIntervalsCoverTheTruthNineteenTimesInTwenty) {
  // 40 runs of other noise and other truths: each parameter's interval must cover its truth in
  // at least 34 (a binomial(40, 0.95) falls below 34 with probability 1.4 %; a 90 % interval
  // passed off as 95 % would fail 4 times in 10).
  int covered_s = 0, covered_g = 0, covered_tau = 0;
  constexpr int runs = 40;
  for (int seed = 1; seed <= runs; ++seed) {
    SyntheticTruth truth;
    truth.scale = 0.6 + 0.035 * seed;
    truth.g = 0.1 + 0.01 * seed;
    truth.tau_s = 8.0 + 0.8 * seed;
    truth.load_noise_N = 0.004;
    const auto m =
        mechanics_of(make_synthetic_run(truth, 100 + static_cast<std::uint64_t>(seed), 10.0, 0.5, 100.0));
    covered_s += covers(m.report.at("stiffness_scale"), truth.scale);
    covered_g += covers(m.report.at("g1"), truth.g);
    covered_tau += covers(m.report.at("tau1_s"), truth.tau_s);
  }
  EXPECT_GE(covered_s, 34);
  EXPECT_GE(covered_g, 34);
  EXPECT_GE(covered_tau, 34);
}

namespace {

// A relaxation (35 s) five times longer than the holds (7 s), ramps at 0.18 mm/s, a 200 Hz
// tester whose loads carry 4.5 mN of noise: the corner where the long calibration missed.
SyntheticTruth long_valley_truth() {
  SyntheticTruth truth;
  truth.scale = 1.3;
  truth.g = 0.4;
  truth.tau_s = 35.0;
  truth.load_noise_N = 0.0045;
  return truth;
}

a::testing::SyntheticRun long_valley_run(std::uint64_t noise_seed) {
  return make_synthetic_run(long_valley_truth(), noise_seed, 7.0, 0.18, 200.0);
}

}  // namespace

// At that corner stiffness, g and tau lie along a long curved valley. The profile's first step
// overshot the crossing several-fold, the refit there ended in a corner (g near 0, tau at its
// cap), and every later point, warm-started from it, stayed there: its rise was huge and the
// interval's end collapsed onto the estimate, so the truth beyond it was missed. This noise seed
// did so (scale 1.2182 [0.1, 1.2182] for a truth of 1.3; seeds 7008, 7018 and 7020 collapsed an
// end too, left out because the sanitizer build runs each for over a minute); over 60 such runs
// the stiffness covered its truth in 44 then, in 58 since each point is also refitted from the
// estimate.
TEST(IdentifyMechanics, ProfileEndsDoNotCollapseOntoTheEstimateAlongALongValley) {
  const SyntheticTruth truth = long_valley_truth();
  const auto m = mechanics_of(long_valley_run(7015));
  for (const auto& [name, value] :
       {std::pair{"stiffness_scale", truth.scale}, {"g1", truth.g}, {"tau1_s", truth.tau_s}}) {
    const auto& p = m.report.at(name);
    // A collapsed end is the estimate itself; an end that the profile found lies a good
    // fraction of a standard error away (the profile rises by 3.84 there).
    EXPECT_GT(p.value - p.lo, 0.1 * p.se) << name;
    EXPECT_GT(p.hi - p.value, 0.1 * p.se) << name;
    EXPECT_TRUE(covers(p, value)) << name << " " << p.value << " [" << p.lo << ", " << p.hi << "]";
  }
}

TEST(IdentifyMechanics, AFitThatDidNotConvergeDeterminesNothing) {
  // The same corner, noise seed 7051: the fit drifts along the valley out of the plausible
  // ranges (g 10.1, stiffness 0.16, tau 130 s) and is still moving after its 300 iterations. Its
  // profile from there once called tau1_s determined, 130 s [38, 148], for a truth of 35 s.
  const auto m = mechanics_of(long_valley_run(7051));
  ASSERT_FALSE(m.report.converged) << "the case this test is about";
  EXPECT_EQ(m.report.iterations, 300);
  int said = 0;
  for (const auto& p : m.report.parameters) {
    EXPECT_FALSE(p.determined) << p.name << " " << p.value << " [" << p.lo << ", " << p.hi << "]";
    EXPECT_FALSE(p.why_not.empty()) << p.name;
    said += p.why_not.find("did not converge") != std::string::npos;
  }
  EXPECT_GE(said, 1) << "the reason is the fit's";
}

TEST(IdentifyMechanics, ASecondRelaxationTimeTheRunDoesNotHaveIsNotDetermined) {
  // One relaxation in the data, two Prony terms asked for: the run cannot give the second
  // term's time, and says so rather than printing a number with a false interval.
  const auto m = mechanics_of(make_synthetic_run(SyntheticTruth{}, 3), 2);
  int undetermined = 0;
  for (const auto& p : m.report.parameters) undetermined += !p.determined;
  EXPECT_GE(undetermined, 1);
  for (const auto& p : m.report.parameters) {
    if (!p.determined) {
      EXPECT_FALSE(p.why_not.empty()) << p.name;
    }
  }
}

TEST(IdentifyMechanics, TooFewHoldsIsAnErrorNamingTheRun) {
  auto run = make_synthetic_run(SyntheticTruth{}, 4);
  run.history.holds.resize(1);
  EXPECT_THROW(a::identify_mechanics(run.history), tocd::Error);
}

TEST(IdentifyClearing, RecoversTheDelayedClearingAndTheEquilibriumTransmissions) {
  const SyntheticTruth truth;
  const auto run = make_synthetic_run(truth, 5);
  const auto c = a::identify_clearing(run.history);
  EXPECT_TRUE(covers(c.report.at("delayed_clearing"), truth.delayed));
  EXPECT_TRUE(covers(c.report.at("delayed_clearing_time_s"), truth.delayed_tau_s));
  ASSERT_EQ(c.T_eq.size(), run.T_eq.size());
  for (std::size_t j = 0; j < c.T_eq.size(); ++j)
    EXPECT_LT(std::abs(c.T_eq[j] - run.T_eq[j]),
              4 * std::sqrt(c.T_eq_covariance(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j))))
        << "knot " << j;
  EXPECT_NEAR(c.report.noise_sigma, truth.transmission_noise, 0.1 * truth.transmission_noise);
}

TEST(IdentifyClearing, IntervalsAreCalibrated) {
  int covered_f = 0, covered_tau = 0;
  constexpr int runs = 40;
  for (int seed = 1; seed <= runs; ++seed) {
    SyntheticTruth truth;
    truth.delayed = 0.05 + 0.01 * seed;
    truth.delayed_tau_s = 8.0 + 0.8 * seed;
    const auto c = a::identify_clearing(
        make_synthetic_run(truth, 200 + static_cast<std::uint64_t>(seed), 10.0, 0.5, 50.0).history);
    covered_f += covers(c.report.at("delayed_clearing"), truth.delayed);
    covered_tau += covers(c.report.at("delayed_clearing_time_s"), truth.delayed_tau_s);
  }
  EXPECT_GE(covered_f, 34);
  EXPECT_GE(covered_tau, 34);
}

// The demo's holds (about 8 s: 2 s, the settling, 5 s of recording) and its meter's noise (0.2 %
// of the light), with the share and the time drawn from the simulated samples' ranges (0 to 0.5,
// 8 to 40 s). A small share leaves the likelihood a second valley (a larger share delayed by
// minutes); before the profiles were scanned over the whole range, intervals taken around the
// wrong valley missed the truth in 15 of these 100 runs. A calibrated 95 % interval misses more
// than 10 times in 100 with probability 1.2 % (binomial). Measured over 400 such runs: the time
// covered in 95.1 % of those where it was determined, the share in 92.3 %; 400 more with noise of
// their own, 93 % (test_identify_clearing_calibration.cpp, physics-long; docs/identify.md).
TEST(IdentifyClearing, IntervalsAreCalibratedOnDemoHoldsWithTheMetersNoise) {
  int determined = 0, missed_f = 0, missed_tau = 0;
  std::vector<int> missed_T_eq(7, 0);
  constexpr int runs = 100;
  std::mt19937_64 draw(77);
  for (int seed = 1; seed <= runs; ++seed) {
    const auto [truth, run] =
        a::testing::demo_holds_clearing_run(draw, 900 + static_cast<std::uint64_t>(seed));
    const auto c = a::identify_clearing(run.history);
    const auto& tau = c.report.at("delayed_clearing_time_s");
    for (std::size_t j = 0; j < missed_T_eq.size(); ++j)
      if (!covers(c.report.parameters[2 + j], run.T_eq[j])) ++missed_T_eq[j];
    if (!covers(c.report.at("delayed_clearing"), truth.delayed)) ++missed_f;
    if (tau.determined) {
      ++determined;
      if (!covers(tau, truth.delayed_tau_s)) ++missed_tau;
    }
  }
  EXPECT_LE(missed_f, 10);
  EXPECT_GE(determined, 80);  // a share below 0.05 or so leaves the time open
  EXPECT_LE(missed_tau, 10);
  // The equilibrium transmissions shift with the share and the time: with Wald intervals 12 to
  // 15 of these 100 missed at every knot. More than 11 misses of 100 has probability 0.4 % at
  // the nominal 95 % (binomial); over 400 runs they cover 93 %, short of 95 % as the share's
  // intervals are (docs/identify.md).
  for (std::size_t j = 0; j < missed_T_eq.size(); ++j) EXPECT_LE(missed_T_eq[j], 11) << "T_eq at knot " << j;
}

TEST(IdentifyClearing, NoDelayLeavesItsTimeUndetermined) {
  SyntheticTruth truth;
  truth.delayed = 0.0;
  const auto c = a::identify_clearing(make_synthetic_run(truth, 6).history);
  EXPECT_FALSE(c.report.at("delayed_clearing_time_s").determined);
  EXPECT_TRUE(covers(c.report.at("delayed_clearing"), 0.0));
}
