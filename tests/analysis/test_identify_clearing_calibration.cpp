// The clearing's intervals against closed-form runs (synthetic_run.hpp) in numbers large enough
// to see a shortfall of a few per cent: 400 runs with the demo's holds (8 s) and its meter's
// noise (0.2 % of the light), the share and the time drawn from the simulated samples' ranges,
// each run's noise from a seed used by no other test. The default suite's 100 runs
// (test_identify_synthetic.cpp) can only tell 95 % from about 90 %.
//
// What it found (December 2026): over the 400 runs of noise seeds 901 to 1300 the share's
// interval had missed in 13 of the 89 runs with a share from 0.4 to 0.5 ((estimate - truth) / se
// scattering with SD 1.24), where 95 % intervals miss 4.5 times in 89. The same truths with the
// noise of seeds 20001 to 20400 missed 6 times, with that of 31001 to 31400 7 times, and 500 runs
// with shares from 0.4 to 0.5 and noise of their own 25 times (SD 0.95 to 0.99): the excess at
// large shares was those draws'. Over the whole range it is not: these 400 runs miss the share
// 28 times (three of them small shares found in the likelihood's other valley, a larger share
// delayed by a minute or more), and seeds 901 to 1300 covered it in 92.3 %: about 93 % against
// 95 %, the shortfall spread over the range; measured, not explained (docs/identify.md). The
// bound below is what calibrated intervals exceed with probability 1 % (31 misses of 400): a
// change that costs the share a few more misses fails this test.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "synthetic_run.hpp"
#include "tocd/analysis/identify_clearing.hpp"

namespace a = tocd::analysis;
using a::testing::covers;

namespace {

// The most misses of n calibrated 95 % intervals that are still likely: the smallest k with
// P(misses > k) below 1 %, from the binomial(n, 0.05) distribution summed term by term.
int most_likely_misses(int n) {
  double tail = 1.0, term = std::pow(0.95, n);  // P(X = 0)
  for (int k = 0; k <= n; ++k) {
    tail -= term;  // now P(X > k)
    if (tail < 0.01) return k;
    term *= (n - k) / (k + 1.0) * (0.05 / 0.95);
  }
  return n;
}

}  // namespace

TEST(BinomialBound, MatchesTheTabulatedQuantiles) {
  // binomial(100, 0.05): P(X > 10) = 0.0115, P(X > 11) = 0.0043; binomial(400, 0.05): P(X > 30)
  // = 0.0114, P(X > 31) = 0.0067 (computed apart, as sums of the binomial terms in exact integers).
  EXPECT_EQ(most_likely_misses(100), 11);
  EXPECT_EQ(most_likely_misses(400), 31);
}

TEST(IdentifyClearing, IntervalsHoldTheTruthAsOftenAsTheySayOverFourHundredFreshRuns) {
  constexpr int runs = 400;
  std::mt19937_64 draw(20261207);
  int share_missed = 0, large = 0, large_missed = 0, determined = 0, time_missed = 0;
  double z_square_large = 0;
  for (int k = 1; k <= runs; ++k) {
    const auto [truth, run] =
        a::testing::demo_holds_clearing_run(draw, 100000 + static_cast<std::uint64_t>(k));
    const auto c = a::identify_clearing(run.history);
    const auto& share = c.report.at("delayed_clearing");
    const auto& time = c.report.at("delayed_clearing_time_s");
    const bool missed = !covers(share, truth.delayed);
    share_missed += missed;
    if (missed)
      std::printf("missed: share %.4f (time %.2f s): %.4f [%.4f, %.4f], time %.2f [%.2f, %.2f]\n",
                  truth.delayed, truth.delayed_tau_s, share.value, share.lo, share.hi, time.value, time.lo,
                  time.hi);
    if (truth.delayed >= 0.4) {
      ++large;
      large_missed += missed;
      const double z = (share.value - truth.delayed) / share.se;
      z_square_large += z * z;
    }
    // Every estimate within what the report calls plausible (one came out at 1003 s of 0.1 to
    // 1000 s before the search's steps were held to the range).
    EXPECT_LE(time.value, time.range.hi) << "run " << k;
    EXPECT_GE(time.value, time.range.lo) << "run " << k;
    if (time.determined) {
      ++determined;
      time_missed += !covers(time, truth.delayed_tau_s);
    }
  }
  std::printf(
      "share missed %d of %d (%d of %d from 0.4 to 0.5, SD of z there %.3f); time missed %d of %d "
      "determined\n",
      share_missed, runs, large_missed, large, std::sqrt(z_square_large / large), time_missed, determined);
  EXPECT_LE(share_missed, most_likely_misses(runs));
  EXPECT_LE(large_missed, most_likely_misses(large));
  EXPECT_GE(determined, 320);  // a share below 0.05 or so leaves the time open: about 1 run in 10
  EXPECT_LE(time_missed, most_likely_misses(determined));
}
