// Tissue models behind the twins: the analytic stand-in's stated formula and the tables.
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/mocks/tissue.hpp"

using namespace tocd::mocks;

TEST(Tissue, AnalyticLoadIsTheStatedPunchFormula) {
  const auto t = make_analytic_tissue(2.5);
  EXPECT_EQ(t->load_N(0.0), 0.0);
  EXPECT_EQ(t->load_N(-1.0), 0.0);
  // 2 a E/(1-nu^2) kappa h eps with a = 1.5, h = 2.5, E = 0.3, nu = 0.49, x = a/h = 0.6.
  const double kappa = 1.0 + 1.33 * 0.6 + 1.33 * 0.216;
  const double k = 2.0 * 1.5 * 0.3 / (1.0 - 0.49 * 0.49) * kappa * 2.5;
  EXPECT_NEAR(t->load_N(1.0), k * -std::log(1.0 - 1.0 / 2.5), 1e-12);
  // Small displacements: linear with the flat-punch stiffness divided by h.
  EXPECT_NEAR(t->load_N(1e-4) / 1e-4, k / 2.5, 1e-3 * k / 2.5);
  // Stiffens with compression, finite at the end stop.
  EXPECT_GT(t->load_N(2.0) - t->load_N(1.5), t->load_N(1.0) - t->load_N(0.5));
  EXPECT_TRUE(std::isfinite(t->load_N(10.0)));
}

TEST(Tissue, AnalyticTransmissionRisesWithCompression) {
  const auto t = make_analytic_tissue(2.5);
  EXPECT_NEAR(t->transmission(0.0), std::exp(-2.5), 1e-12);  // Beer-Lambert, mu_eff 1/mm
  double last = t->transmission(0.0);
  for (double d = 0.1; d < 2.3; d += 0.1) {
    const double now = t->transmission(d);
    EXPECT_GT(now, last) << d;
    EXPECT_LE(now, 1.0);
    last = now;
  }
}

TEST(Tissue, TabulatedInterpolatesLinearlyAndHoldsTheEnds) {
  const auto t = make_tabulated_tissue({0.0, 1.0, 2.0}, {0.0, 2.0, 6.0}, {0.1, 0.2, 0.4});
  EXPECT_DOUBLE_EQ(t->load_N(0.5), 1.0);
  EXPECT_DOUBLE_EQ(t->load_N(1.5), 4.0);
  EXPECT_DOUBLE_EQ(t->transmission(1.25), 0.25);
  EXPECT_DOUBLE_EQ(t->load_N(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(t->transmission(9.0), 0.4);
}

TEST(Tissue, BadTablesAreRefused) {
  EXPECT_THROW(make_tabulated_tissue({0.0}, {0.0}, {0.1}), tocd::ConfigError);
  EXPECT_THROW(make_tabulated_tissue({0.0, 1.0}, {0.0}, {0.1, 0.2}), tocd::ConfigError);
  EXPECT_THROW(make_tabulated_tissue({0.0, 0.0}, {0.0, 1.0}, {0.1, 0.2}), tocd::ConfigError);
  EXPECT_THROW(make_tabulated_tissue({0.0, 1.0}, {0.0, NAN}, {0.1, 0.2}), tocd::ConfigError);
  // Relative to the glass-only reference T may exceed 1 a little (frustrated TIR at the pin tip).
  EXPECT_NO_THROW(make_tabulated_tissue({0.0, 1.0}, {0.0, 1.0}, {0.1, 1.2}));
  EXPECT_THROW(make_tabulated_tissue({0.0, 1.0}, {0.0, 1.0}, {0.1, 2.5}), tocd::ConfigError);
  EXPECT_THROW(make_tabulated_tissue({0.0, 1.0}, {0.0, 1.0}, {-0.1, 0.5}), tocd::ConfigError);
  AnalyticTissueParams p;
  p.poisson_ratio = 0.5;
  EXPECT_THROW(make_analytic_tissue(p), tocd::ConfigError);
  EXPECT_THROW(make_analytic_tissue(-1.0), tocd::ConfigError);
}
