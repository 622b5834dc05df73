// Profile-likelihood intervals (identified.hpp) on cost profiles whose crossings are known in
// closed form: the interval ends are where the profile rises by z^2, nothing else. The search
// stops once sqrt(rise) is within 1e-3 of z, so each end is good to 1e-3 / |d sqrt(rise)/dv|.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/analysis/identified.hpp"

namespace a = tocd::analysis;

namespace {

constexpr double kZ = 1.959963984540054;

a::IdentifiedParameter parameter(double value, double se, a::PlausibleRange range) {
  a::IdentifiedParameter p;
  p.name = "x";
  p.value = value;
  p.se = se;
  p.range = range;
  return p;
}

}  // namespace

TEST(ProfileInterval, AQuadraticProfileGivesTheWaldInterval) {
  // rise = ((v - 2) / 0.1)^2: the crossing of z^2 is at 2 +- 0.1 z exactly.
  auto p = parameter(2.0, 0.1, {0.0, 10.0, false});
  a::apply_profile(p, [](double v) { return std::pow((v - 2.0) / 0.1, 2); });
  EXPECT_EQ(p.interval, "profile");
  EXPECT_NEAR(p.lo, 2.0 - 0.1 * kZ, 1e-3 * 0.1);
  EXPECT_NEAR(p.hi, 2.0 + 0.1 * kZ, 1e-3 * 0.1);
  EXPECT_TRUE(p.determined);
}

TEST(ProfileInterval, ACurvedValleyGivesItsOwnAsymmetricEnds) {
  // rise = (ln(v / 30) / 0.2)^2 on a linear axis, with a Wald se (3) that knows nothing of the
  // curvature: the ends are 30 exp(-+0.2 z) = 20.3 and 44.4, not 30 -+ 5.9.
  auto p = parameter(30.0, 3.0, {0.0, 1000.0, false});
  a::apply_profile(p, [](double v) { return v > 0 ? std::pow(std::log(v / 30.0) / 0.2, 2) : 1e300; });
  const double lo = 30.0 * std::exp(-0.2 * kZ), hi = 30.0 * std::exp(0.2 * kZ);
  EXPECT_NEAR(p.lo, lo, 1e-3 * 0.2 * lo);  // d sqrt(rise)/dv = 1 / (0.2 v)
  EXPECT_NEAR(p.hi, hi, 1e-3 * 0.2 * hi);
}

TEST(ProfileInterval, AProfileThatStaysLowRunsToTheRangeAndIsNotDetermined) {
  // The cost rises to at most 2 residual variances above the estimate: the run bounds
  // nothing above it, and says so.
  auto p = parameter(20.0, 2.0, {0.1, 1000.0, true});
  a::apply_profile(p, [](double v) {
    const double u = std::log(v / 20.0) / 0.1;
    return v < 20.0 ? u * u : 2.0 * (1 - std::exp(-u * u));
  });
  const double lo = 20.0 * std::exp(-0.1 * kZ);
  EXPECT_NEAR(p.lo, lo, 1e-3 * 0.1 * lo);
  EXPECT_DOUBLE_EQ(p.hi, 1000.0);
  EXPECT_FALSE(p.determined);
  EXPECT_NE(p.why_not.find("above"), std::string::npos) << p.why_not;
}

TEST(ProfileInterval, AnIntervalOpenAtTheRangesEndIsABoundNotAValue) {
  // Closed below at 200 s, open above: on the log scale of 0.1 .. 1000 s that is only 18 % of
  // the plausible range, yet the run bounds the time from below alone. Not determined.
  auto p = parameter(400.0, 50.0, {0.1, 1000.0, true});
  a::apply_profile(p, [](double v) {
    const double u = std::log(v / 400.0) / std::log(2.0) * kZ;
    return v < 400.0 ? u * u : 0.5 * (1 - std::exp(-u * u));
  });
  EXPECT_NEAR(p.lo, 200.0, 1e-3 * 200.0);
  EXPECT_DOUBLE_EQ(p.hi, 1000.0);
  EXPECT_FALSE(p.determined);
  EXPECT_NE(p.why_not.find("does not bound it above"), std::string::npos) << p.why_not;
}

TEST(ProfileInterval, AWideButClosedIntervalIsNotDetermined) {
  // Closed on both sides, but half the plausible range wide: the run says little.
  auto p = parameter(0.5, 0.15, {0.0, 1.0, false});
  a::apply_profile(p, [](double v) { return std::pow((v - 0.5) / 0.15, 2); });
  EXPECT_NEAR(p.hi - p.lo, 2 * 0.15 * kZ, 2 * 1e-3 * 0.15);
  EXPECT_FALSE(p.determined);
}

// A profile walked out from its estimate at 2 (rise ((v - 2) / 0.1)^2 there, closing at
// 2 +- 0.196), with a second valley `valley` elsewhere, then widened by a scan of the range
// [0, 10] in steps of `step`.
template <class Valley>
a::IdentifiedParameter widened_by_scan(Valley valley, double step) {
  auto rise = [&](double v) { return std::min(std::pow((v - 2.0) / 0.1, 2), valley(v)); };
  auto p = parameter(2.0, 0.1, {0.0, 10.0, false});
  a::apply_profile(p, rise);
  EXPECT_NEAR(p.hi, 2.0 + 0.1 * kZ, 1e-3 * 0.1);  // the walk stops before the second valley
  std::vector<std::pair<double, double>> scan;
  for (int i = 0; i * step <= 10.0 + 1e-9; ++i) scan.emplace_back(i * step, rise(i * step));
  a::widen_to_profile_hull(p, scan);
  return p;
}

// The second valley at 3 has a rise of 1: below z^2, so a value there is as consistent with
// the run as the interval's ends, and the interval is widened to hold it.
TEST(ProfileInterval, ASecondValleyBelowZSquaredWidensTheInterval) {
  const auto p = widened_by_scan([](double v) { return 1 + std::pow((v - 3.0) / 0.1, 2); }, 0.05);
  // Grid points below z^2 near 3: 2.85 .. 3.15 (rise 1 + 2.25 = 3.25 at 2.85); the end runs to
  // the next grid point, 3.2. Below, nothing new: the low end stays.
  EXPECT_NEAR(p.lo, 2.0 - 0.1 * kZ, 1e-3 * 0.1);
  EXPECT_DOUBLE_EQ(p.hi, 3.2);
  EXPECT_TRUE(p.lo <= 3.0 && 3.0 <= p.hi);
}

TEST(ProfileInterval, ASecondValleyAtTheRangesEndLeavesThatSideOpen) {
  const auto p = widened_by_scan([](double v) { return 1 + std::pow((v - 9.5) / 0.5, 2); }, 0.1);
  EXPECT_DOUBLE_EQ(p.hi, 10.0);
  EXPECT_FALSE(p.determined);
  EXPECT_NE(p.why_not.find("above"), std::string::npos) << p.why_not;
}

// A linear parameter's profile over a valley of the nonlinear ones (widen_over_valley): at a
// point whose cost sits `rise` residual variances above the minimum, the cost grows by
// (x - x_hat)^2 / var, so the values kept are x_hat +- sqrt((z^2 - rise) var), by hand here.
TEST(ValleyInterval, APointUpTheValleyWidensByWhatIsLeftOfZSquared) {
  auto p = parameter(0.5, 0.025, {0.0, 1.5, false});
  p.lo = 0.45;
  p.hi = 0.55;
  const double rss_min = 100.0, variance = 2.0;  // residual variance 2: rises are costs / 2
  std::vector<a::ValleyPoint> valley{
      {rss_min + 1.0 * variance, {0.6}, {0.0004}},   // rise 1: half-width sqrt(2.8415 * 0.0008)
      {rss_min + 5.0 * variance, {0.1}, {0.0004}},   // rise 5, above z^2: not in the interval
      {rss_min + 0.5 * variance, {0.05}, {0.0}},     // no curvature information: left out
      {rss_min + 0.2 * variance, {0.48}, {0.0001}},  // inside the Wald interval already
  };
  a::widen_over_valley(p, 0, valley, rss_min, variance);
  EXPECT_EQ(p.interval, "profile");
  EXPECT_DOUBLE_EQ(p.lo, 0.45);
  EXPECT_NEAR(p.hi, 0.6 + std::sqrt((kZ * kZ - 1.0) * 0.0004 * variance), 1e-12);
  EXPECT_TRUE(p.determined);
}

TEST(ValleyInterval, AValleyInsideTheWaldIntervalLeavesIt) {
  auto p = parameter(0.5, 0.025, {0.0, 1.5, false});
  p.lo = 0.45;
  p.hi = 0.55;
  a::widen_over_valley(p, 0, {{1.0, {0.5}, {0.0001}}}, 1.0, 1.0);
  EXPECT_EQ(p.interval, "wald");
  EXPECT_DOUBLE_EQ(p.hi, 0.55);
}
