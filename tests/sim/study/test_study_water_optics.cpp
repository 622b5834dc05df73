// The water-content optics mapping against values worked out by hand from its definition
// (docs/water.md): n(w) = 1.33 w + 1.53 (1 - w); f = (n - 1.38) / (1.518 - 1.38).
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/study/water_optics.hpp"

namespace {

using namespace tocd::sim::study;

TEST(WaterOptics, NativeWaterFractionFollowsFromTheIndexMix) {
  const WaterOptics w;
  EXPECT_NEAR(native_water_fraction(w), 0.75, 1e-12);  // (1.53 - 1.38) / 0.2
  EXPECT_NEAR(mixed_index(0.75, w), 1.38, 1e-12);
  EXPECT_NEAR(mixed_index(0.0, w), 1.53, 1e-12);
}

TEST(WaterOptics, ClearingFractionAndOpticsAtHandWorkedPoints) {
  const WaterOptics w;
  EXPECT_NEAR(water_clearing_fraction(0.75, w), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(water_clearing_fraction(0.9, w), 0.0);  // swollen: no clearing
  // w = 0.4: n = 0.532 + 0.918 = 1.45, f = 0.07 / 0.138.
  const double f = 0.07 / 0.138;
  EXPECT_NEAR(water_clearing_fraction(0.4, w), f, 1e-12);
  EXPECT_EQ(water_level(0.4, w), 4);                          // round(0.507 * 8)
  EXPECT_NEAR(water_clearing_fraction(0.06, w), 1.0, 1e-12);  // n = 1.518: the cleared state
  EXPECT_EQ(water_level(std::nan(""), w), 0);
  const auto optics = water_optics(w);
  // Level 4: optics at f = 4/8 between native and cleared.
  const auto& o = optics.regions.at(kGradedRegionBase + 4);
  EXPECT_NEAR(o.mu_s_per_mm, 28.9 + 0.5 * (17.34 - 28.9), 1e-12);
  EXPECT_NEAR(o.mu_a_per_mm, 0.089 + 0.5 * (0.0534 - 0.089), 1e-12);
  EXPECT_NEAR(o.n, 1.38 + 0.5 * (1.518 - 1.38), 1e-12);
}

TEST(WaterOptics, RefusesEndPointsOutsideTheMix) {
  WaterOptics w;
  w.graded.native.n = 1.6;
  EXPECT_THROW(native_water_fraction(w), tocd::ConfigError);
  w = WaterOptics{};
  w.graded.bins = 0;
  EXPECT_THROW(water_level(0.5, w), tocd::ConfigError);
}

}  // namespace
