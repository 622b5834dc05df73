// Inverse FE: the Ogden law identified from a pin-compression load-displacement curve with
// the FE in the loop. The expectations are the known truth the data were made from, never
// what the fit printed.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "tocd/sim/fe/inverse_fit.hpp"
#include "tocd/sim/fe/solve.hpp"

namespace fe = tocd::sim::fe;
namespace mat = tocd::sim::material;

namespace {

fe::PinCompressionData coarse_dataset(const mat::OgdenParameters& truth, double noise, unsigned seed,
                                      std::vector<double>& true_force) {
  fe::PinCompressionData d;
  d.model = fe::FeModel::published_default();
  d.model.mesh_refinement = 0.5;  // coarse: the data and the fit share the mesh, so its error cancels
  for (int k = 1; k <= 12; ++k) d.displacement_mm.push_back(0.1 * k);
  true_force = fe::pin_force_curve(d, truth);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  for (double f : true_force) d.load_N.push_back(f * (1 + n(rng)));
  return d;
}

}  // namespace

#ifndef TOCD_INVERSE_LONG

TEST(InverseFit, RecoversAKnownOneTermLawFromNoisyFeData) {
  // Truth: a one-term Ogden skin (mu > 0, alpha < 0: stiffening in compression, stable),
  // D_1 from nu = 0.49 as the fit assumes.
  mat::OgdenParameters truth{{0.003}, {-4.0}, {}};
  truth.D = {3 * (1 - 2 * 0.49) / (0.003 * 1.49)};
  std::vector<double> true_force;
  const auto data = coarse_dataset(truth, 0.005, 20261202, true_force);
  ASSERT_EQ(true_force.size(), 12u);

  fe::InverseFitOptions o;
  o.model = fe::InverseModel::ogden1;  // starts from the published ogden3 scaled, reduced to one term
  o.confidence = 0.99;                 // two parameters: the truth falls outside by chance in ~2 % of seeds
  const auto r = fe::fit_material({data}, {}, o);
  ASSERT_TRUE(r.converged) << r.stop_reason;
  ASSERT_EQ(r.names.size(), 2u);

  // The fitted force curve against the noise-free truth: 0.5 % noise on 12 points leaves a
  // curve error of ~0.5 % x sqrt(2 / 12) = 0.2 %; 1 % is five of those.
  const auto fitted = fe::pin_force_curve(data, r.material);
  ASSERT_EQ(fitted.size(), true_force.size());
  for (std::size_t k = 0; k < fitted.size(); ++k)
    EXPECT_NEAR(fitted[k], true_force[k], 0.01 * true_force[k]) << "d = " << data.displacement_mm[k];

  // The truth inside the reported intervals, and the intervals informative (narrower than
  // 25 % of the value: a fit that learnt nothing would fail here).
  const double want[] = {truth.mu[0], truth.alpha[0]};
  for (int k = 0; k < 2; ++k)
    std::printf("%s: truth %.6g, fitted %.6g, 99 %% interval [%.6g, %.6g]\n", r.names[k].c_str(), want[k],
                r.values[k], r.interval_low[k], r.interval_high[k]);
  std::printf("%d iterations, %d FE solves; residual variance %.3g\n", r.iterations, r.evaluations,
              r.residual_variance);
  for (int k = 0; k < 2; ++k) {
    EXPECT_GE(want[k], r.interval_low[k]) << r.names[k];
    EXPECT_LE(want[k], r.interval_high[k]) << r.names[k];
    EXPECT_LT(r.interval_high[k] - r.interval_low[k], 0.5 * std::abs(want[k])) << r.names[k];
  }
  // Residual variance: the relative noise put in (0.5 %)^2, within chi-square scatter of 10
  // degrees of freedom (s^2 / sigma^2 in [0.25, 2.2] covers 99 %).
  EXPECT_GT(r.residual_variance, 0.25 * 0.005 * 0.005);
  EXPECT_LT(r.residual_variance, 2.2 * 0.005 * 0.005);
  EXPECT_TRUE(r.stability.stable) << r.stability.first_failure;
}

TEST(InverseFit, JointFitWithClosedFormsPinsTheScale) {
  // Closed-form uniaxial and simple-shear data of the scaled published law plus no FE: the
  // `scaled` model must return the factor exactly (the model is linear in it).
  const double s = 1.7;
  mat::OgdenParameters truth = mat::OgdenParameters::published_skin();
  for (double& m : truth.mu) m *= s;
  fe::ClosedFormData uni{"uniaxial", mat::LoadingMode::uniaxial, {}, {}, 1.0};
  fe::ClosedFormData shear{"shear", mat::LoadingMode::simple_shear, {}, {}, 2.0};
  for (int k = 1; k <= 8; ++k) {
    uni.x.push_back(1 - 0.06 * k);
    uni.stress_MPa.push_back(mat::ogden_nominal_stress(truth, uni.mode, uni.x.back()));
    shear.x.push_back(0.1 * k);
    shear.stress_MPa.push_back(mat::ogden_nominal_stress(truth, shear.mode, shear.x.back()));
  }
  fe::InverseFitOptions o;
  o.model = fe::InverseModel::scaled;
  const auto r = fe::fit_material({}, {uni, shear}, o);
  ASSERT_EQ(r.values.size(), 1u);
  EXPECT_NEAR(r.values[0], s, 1e-9 * s);
  EXPECT_LT(r.datasets[0].max_abs_relative, 1e-9);
  EXPECT_LT(r.datasets[1].max_abs_relative, 1e-9);
}

TEST(InverseFit, BadDataIsNamed) {
  fe::PinCompressionData d;
  d.displacement_mm = {0.5, 0.4};
  d.load_N = {0.01, 0.02};
  EXPECT_THROW(fe::fit_material({d}, {}), mat::MaterialError);
  d.displacement_mm = {0.5};
  EXPECT_THROW(fe::fit_material({d}, {}), mat::MaterialError);
  EXPECT_THROW(fe::fit_material({}, {}), mat::MaterialError);
  EXPECT_THROW(fe::parse_inverse_model("ogden4"), mat::MaterialError);
}

#else

TEST(InverseFitLong, DemoSampleFittedLawMatchesLoadsWhereTheDefaultLawDoesNot) {
  // The demo's simulated sample (mocks/sim_tissue.hpp, SimTissueSpec's defaults): the published
  // law with shear moduli x 1.25 (D_1 / 1.25), 2.0 mm thick, tabulated at 0.25 .. 1.5 mm. Its
  // loads are what the simulated tester reports.
  const struct {
    double stiffness_scale = 1.25, thickness_mm = 2.0;
    std::vector<double> displacements_mm{0.25, 0.5, 0.75, 1.0, 1.25, 1.5};
  } spec;
  mat::OgdenParameters truth = mat::OgdenParameters::published_skin();
  for (double& m : truth.mu) m *= spec.stiffness_scale;
  for (double& d : truth.D) d /= spec.stiffness_scale;
  fe::PinCompressionData data;
  data.model = fe::FeModel::published_default();
  data.model.thickness_mm = spec.thickness_mm;
  data.displacement_mm = spec.displacements_mm;
  data.load_N = fe::pin_force_curve(data, truth);
  ASSERT_EQ(data.load_N.size(), spec.displacements_mm.size());

  const auto defaults = fe::pin_force_curve(data, mat::OgdenParameters::published_skin());
  fe::InverseFitOptions o;
  o.model = fe::InverseModel::scaled;  // the law `tocdlab compare --material fitted` uses
  const auto r = fe::fit_material({data}, {}, o);
  std::printf("stiffness factor %.5f, 95 %% interval [%.5f, %.5f]\n", r.values[0], r.interval_low[0],
              r.interval_high[0]);
  const auto fitted = fe::pin_force_curve(data, r.material);
  ASSERT_EQ(fitted.size(), data.load_N.size());
  int default_misses = 0;
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    const double meas = data.load_N[k];
    std::printf("d = %.3f mm: measured %.5f N, fitted %.5f N (%+.2f %%), default law %.5f N (%+.2f %%)\n",
                data.displacement_mm[k], meas, fitted[k], 100 * (fitted[k] / meas - 1), defaults[k],
                100 * (defaults[k] / meas - 1));
    EXPECT_NEAR(fitted[k], meas, 0.05 * meas) << "d = " << data.displacement_mm[k];
    default_misses += std::abs(defaults[k] - meas) > 0.05 * meas;
  }
  EXPECT_EQ(default_misses, static_cast<int>(fitted.size()));  // the default law misses every step
  EXPECT_TRUE(r.stability.stable) << r.stability.first_failure;
}

#endif
