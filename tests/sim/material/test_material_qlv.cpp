// Quasi-linear viscoelasticity against its closed forms (Fung 1993, ch. 7): step and hold,
// ramp and hold, and a quadratic history, whose hereditary integrals are worked out by hand
// below, independently of the recursion in qlv.cpp.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/material/qlv.hpp"

namespace m = tocd::sim::material;

namespace {

// Ramp of the elastic load from 0 to e1 over [0, tr], held after: integral of
// exp(-(t-u)/tau) dF_e(u) = (e1/tr) tau (1 - exp(-t/tau)) on the ramp, and its end value
// decaying as exp(-(t-tr)/tau) during the hold.
double ramp_hold_h(double t, double e1, double tr, double tau) {
  if (t <= tr) return e1 / tr * tau * (1.0 - std::exp(-t / tau));
  return e1 / tr * tau * (1.0 - std::exp(-tr / tau)) * std::exp(-(t - tr) / tau);
}

}  // namespace

TEST(Qlv, StepAndHoldRelaxesAsTheReducedRelaxationFunction) {
  // An instantaneous step (two samples at t = 0) to e1, then a hold: F(t) = e1 K(t).
  const double e1 = 2.0;
  const m::PronySeries prony{{{0.3, 20.0}, {0.1, 2.0}}};
  std::vector<double> t{0.0, 0.0}, e{0.0, e1};
  for (double s = 0.5; s <= 60.0; s += 0.5) {
    t.push_back(s);
    e.push_back(e1);
  }
  const auto f = m::qlv_response(t, e, prony);
  for (std::size_t n = 1; n < t.size(); ++n)
    EXPECT_NEAR(f[n], e1 * (1.0 + 0.3 * std::exp(-t[n] / 20.0) + 0.1 * std::exp(-t[n] / 2.0)), 1e-13) << t[n];
  EXPECT_DOUBLE_EQ(prony.instantaneous(), 1.4);
  EXPECT_NEAR(prony.relaxation(20.0), 1.0 + 0.3 / M_E + 0.1 * std::exp(-10.0), 1e-15);
}

TEST(Qlv, RampAndHoldIsExactOnAnyGridThatHasTheRampsEnds) {
  // The recursion is exact for an elastic load linear in time between samples, so a ramp
  // sampled only at its two ends gives the closed form to round-off, as does a fine grid.
  const double e1 = 1.5, tr = 3.0, tau = 7.0;
  for (const double dt : {3.0, 0.37, 0.001}) {
    std::vector<double> t, e;
    for (double s = 0.0; s < tr; s += dt) {
      t.push_back(s);
      e.push_back(e1 * s / tr);
    }
    t.push_back(tr);
    e.push_back(e1);
    for (double s = tr + 0.25; s <= 40.0; s += 0.25) {
      t.push_back(s);
      e.push_back(e1);
    }
    const auto h = m::prony_history(t, e, tau);
    for (std::size_t n = 0; n < t.size(); ++n)
      ASSERT_NEAR(h[n], ramp_hold_h(t[n], e1, tr, tau), 1e-12) << "dt " << dt << " t " << t[n];
  }
}

TEST(Qlv, QuadraticHistoryConvergesAtSecondOrder) {
  // F_e = t^2: h(t) = integral of exp(-(t-u)/tau) 2u du = 2 tau (t - tau (1 - exp(-t/tau))).
  // Linear interpolation of F_e between samples errs by O(dt^2), so halving dt quarters the error.
  const double tau = 1.3, t_end = 4.0;
  auto error_at = [&](double dt) {
    std::vector<double> t, e;
    const int n = static_cast<int>(std::lround(t_end / dt));
    for (int k = 0; k <= n; ++k) {
      t.push_back(k * dt);
      e.push_back(k * dt * k * dt);
    }
    const auto h = m::prony_history(t, e, tau);
    return std::abs(h.back() - 2 * tau * (t_end - tau * (1 - std::exp(-t_end / tau))));
  };
  const double e1 = error_at(0.04), e2 = error_at(0.02);
  EXPECT_GT(e1, 0.0);
  EXPECT_NEAR(e1 / e2, 4.0, 0.1);
}

TEST(Qlv, TauDerivativeMatchesTheClosedFormsDerivative) {
  // d h / d tau of the ramp-and-hold closed form by central differences of the closed form
  // (step 1e-5 tau: truncation ~1e-10 relative) against the differentiated recursion.
  const double e1 = 1.5, tr = 0.5, tau = 20.0;
  std::vector<double> t, e;
  for (double s = 0.0; s <= 30.0; s += 0.01) {
    t.push_back(s);
    e.push_back(e1 * std::min(s, tr) / tr);
  }
  std::vector<double> dh;
  m::prony_history(t, e, tau, &dh);
  const double step = 1e-5 * tau;
  for (std::size_t n = 0; n < t.size(); n += 97) {
    const double fd =
        (ramp_hold_h(t[n], e1, tr, tau + step) - ramp_hold_h(t[n], e1, tr, tau - step)) / (2 * step);
    EXPECT_NEAR(dh[n], fd, 1e-9 + 1e-6 * std::abs(fd)) << t[n];
  }
}

TEST(Qlv, BadInputIsRefusedNamingIt) {
  EXPECT_THROW(m::prony_history({0.0, 1.0}, {0.0}, 1.0), m::MaterialError);
  EXPECT_THROW(m::prony_history({0.0, 1.0}, {0.0, 1.0}, 0.0), m::MaterialError);
  EXPECT_THROW(m::prony_history({1.0, 0.0}, {0.0, 1.0}, 1.0), m::MaterialError);
  const m::PronySeries negative{{{-0.1, 1.0}}};
  try {
    negative.validate();
    FAIL() << "a negative g was accepted";
  } catch (const m::MaterialError& e) {
    EXPECT_NE(std::string(e.what()).find("Prony term 1"), std::string::npos) << e.what();
  }
}
