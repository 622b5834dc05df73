// Closed-form stresses of homogeneous tests and the least-squares machinery behind the joint
// fits: each closed form against an independent derivative of the strain energy, the t
// quantile against tabulated values, and a fit whose answer is known.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tocd/sim/material/least_squares.hpp"
#include "tocd/sim/material/loading_modes.hpp"

namespace mat = tocd::sim::material;

namespace {

// Incompressible Abaqus-form Ogden energy of principal stretches, written out here.
double energy(const mat::OgdenParameters& p, double l1, double l2, double l3) {
  double w = 0;
  for (std::size_t i = 0; i < p.mu.size(); ++i) {
    const double a = p.alpha[i];
    w += 2 * p.mu[i] / (a * a) * (std::pow(l1, a) + std::pow(l2, a) + std::pow(l3, a) - 3);
  }
  return w;
}

// Central difference of a one-parameter energy path: the work-conjugate nominal stress.
template <class F>
double derivative(F f, double x) {
  const double h = 1e-5;
  return (f(x + h) - f(x - h)) / (2 * h);
}

}  // namespace

TEST(LoadingModes, ClosedFormsAreTheEnergyDerivativeOfEachDeformationPath) {
  const auto p = mat::OgdenParameters::published_skin();
  for (double x : {0.5, 0.8, 0.95, 1.1, 1.4}) {
    // Uniaxial: W(lambda, lambda^-1/2, lambda^-1/2), P = dW/dlambda.
    const double uni =
        derivative([&](double l) { return energy(p, l, 1 / std::sqrt(l), 1 / std::sqrt(l)); }, x);
    EXPECT_NEAR(mat::ogden_nominal_stress(p, mat::LoadingMode::uniaxial, x), uni,
                1e-7 + 1e-6 * std::abs(uni));
    // Equibiaxial: two directions do work, P = (1/2) dW/dlambda.
    const double bi = 0.5 * derivative([&](double l) { return energy(p, l, l, 1 / (l * l)); }, x);
    EXPECT_NEAR(mat::ogden_nominal_stress(p, mat::LoadingMode::equibiaxial, x), bi,
                1e-7 + 1e-6 * std::abs(bi));
  }
  for (double g : {0.05, 0.3, 0.8, 1.5}) {
    // Simple shear by the amount g: principal stretches of F = [[1, g], [0, 1]] from C.
    auto w = [&](double gamma) {
      const double tr = 2 + gamma * gamma;  // trace of C in the shear plane, det C = 1
      const double l1 = std::sqrt(0.5 * (tr + std::sqrt(tr * tr - 4)));
      return energy(p, l1, 1 / l1, 1.0);
    };
    const double shear = derivative(w, g);
    EXPECT_NEAR(mat::ogden_nominal_stress(p, mat::LoadingMode::simple_shear, g), shear,
                1e-7 + 1e-6 * std::abs(shear));
  }
  // Small shear: the initial shear modulus.
  EXPECT_NEAR(mat::ogden_nominal_stress(p, mat::LoadingMode::simple_shear, 1e-4) / 1e-4,
              p.initial_shear_modulus(), 1e-6 * p.initial_shear_modulus());
}

TEST(LoadingModes, BadInputIsNamed) {
  const auto p = mat::OgdenParameters::published_skin();
  EXPECT_THROW(mat::ogden_nominal_stress(p, mat::LoadingMode::uniaxial, 0.0), mat::MaterialError);
  EXPECT_THROW(mat::ogden_nominal_stress(p, mat::LoadingMode::equibiaxial, NAN), mat::MaterialError);
  EXPECT_THROW(mat::parse_loading_mode("torsion"), mat::MaterialError);
  EXPECT_EQ(mat::parse_loading_mode("simple-shear"), mat::LoadingMode::simple_shear);
}

TEST(LeastSquares, StudentQuantileMatchesTables) {
  // Two-sided values from any t table.
  EXPECT_NEAR(mat::student_t_quantile(0.95, 3), 3.182, 0.01);
  EXPECT_NEAR(mat::student_t_quantile(0.95, 10), 2.228, 0.002);
  EXPECT_NEAR(mat::student_t_quantile(0.99, 5), 4.032, 0.03);
  EXPECT_NEAR(mat::student_t_quantile(0.95, 1e6), 1.960, 0.001);
}

TEST(LeastSquares, RecoversAnExponentialWithCoverageOfItsIntervals) {
  // y = a exp(b x) with 1 % noise; over 200 seeds the 95 % intervals must cover the truth in
  // about 95 % of fits (binomial SE 1.5 %, so [0.90, 0.99] is a > 3 sigma band).
  const double a = 2.0, b = -1.3;
  int covered_a = 0, covered_b = 0;
  const int trials = 200;
  for (int seed = 0; seed < trials; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0, 0.01);
    std::vector<double> xs, ys;
    for (int k = 0; k < 15; ++k) {
      xs.push_back(0.2 * k);
      ys.push_back(a * std::exp(b * xs.back()) + noise(rng));
    }
    mat::LeastSquaresProblem pr;
    pr.names = {"a", "b"};
    pr.start = Eigen::Vector2d(1.0, -0.5);
    pr.difference_step = Eigen::Vector2d(1e-6, 1e-6);
    pr.residuals = [&](const Eigen::VectorXd& t) -> std::optional<Eigen::VectorXd> {
      Eigen::VectorXd r(xs.size());
      for (std::size_t k = 0; k < xs.size(); ++k) r[k] = t[0] * std::exp(t[1] * xs[k]) - ys[k];
      return r;
    };
    const auto res = mat::levenberg_marquardt(pr);
    ASSERT_TRUE(res.converged) << res.stop_reason;
    covered_a += std::abs(res.theta[0] - a) <= res.interval_half_width[0];
    covered_b += std::abs(res.theta[1] - b) <= res.interval_half_width[1];
  }
  EXPECT_GE(covered_a, 0.90 * trials);
  EXPECT_LE(covered_a, 0.99 * trials);
  EXPECT_GE(covered_b, 0.90 * trials);
  EXPECT_LE(covered_b, 0.99 * trials);
}

TEST(LeastSquares, TooFewPointsOrAnUnevaluableStartIsRefused) {
  mat::LeastSquaresProblem pr;
  pr.names = {"a", "b"};
  pr.start = Eigen::Vector2d(1, 1);
  pr.difference_step = Eigen::Vector2d(1e-6, 1e-6);
  pr.residuals = [](const Eigen::VectorXd& t) -> std::optional<Eigen::VectorXd> {
    return Eigen::Vector2d(t[0], t[1]);
  };
  EXPECT_THROW(mat::levenberg_marquardt(pr), mat::MaterialError);
  pr.residuals = [](const Eigen::VectorXd&) -> std::optional<Eigen::VectorXd> { return std::nullopt; };
  EXPECT_THROW(mat::levenberg_marquardt(pr), mat::MaterialError);
}
