// The biphasic element's analytic tangent against central finite differences of its residual,
// and the refusal of bad input.
#include <random>

#include <gtest/gtest.h>

#include "poro_test_models.hpp"
#include "tocd/sim/poro/solver.hpp"

namespace {

using namespace tocd::sim::poro;

PoroModel small_model(Kinematics k) {
  PoroModel m;
  m.kinematics = k;
  m.mesh = {2.0, 1.0, 2, 2, 1.0};
  m.skeleton = reference::skeleton(0.01, 0.3);
  m.permeability = {0.5, 0.2, 2.0, 3.0};  // strain-dependent: exercises the dk/dJ terms
  m.left.fix_x = true;
  m.bottom.fix_y = true;
  m.right.drained = true;
  return m;
}

// Central differences have truncation error O(h^2 |R'''|) and round-off O(eps |R| / h); with
// h = 1e-6 of the dof scale both are below 1e-6 of the tangent's largest entry.
void expect_tangent_matches_differences(Kinematics k) {
  PoroSolver solver(small_model(k));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int e : {0, 3}) {
    Eigen::VectorXd x(22), prev(22);
    for (int i = 0; i < 18; ++i) {
      x[i] = 0.08 * U(rng);  // up to 8 % of the element size: finite strain
      prev[i] = 0.02 * U(rng);
    }
    for (int i = 18; i < 22; ++i) {
      x[i] = 0.01 * U(rng);  // pressures of the order of the shear modulus
      prev[i] = 0;
    }
    const double dt = 0.3;
    const auto at = solver.element_check(e, x, prev, dt);
    const double scale = at.tangent.cwiseAbs().maxCoeff();
    for (int j = 0; j < 22; ++j) {
      const double h = j < 18 ? 1e-6 : 1e-8;
      Eigen::VectorXd xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      const Eigen::VectorXd fd =
          (solver.element_check(e, xp, prev, dt).residual - solver.element_check(e, xm, prev, dt).residual) /
          (2 * h);
      for (int i = 0; i < 22; ++i)
        EXPECT_NEAR(at.tangent(i, j), fd[i], 1e-6 * scale)
            << "element " << e << " entry (" << i << ", " << j << ")";
    }
  }
}

TEST(PoroElement, TangentMatchesFiniteDifferencesPlaneStrain) {
  expect_tangent_matches_differences(Kinematics::plane_strain);
}

TEST(PoroElement, TangentMatchesFiniteDifferencesAxisymmetric) {
  expect_tangent_matches_differences(Kinematics::axisymmetric);
}

TEST(PoroElement, HolmesMowPermeabilityForm) {
  const Permeability k{2.0, 0.25, 1.5, 4.0};
  // At J = 1 both factors are 1.
  EXPECT_DOUBLE_EQ(k.at(1.0), 2.0);
  // J = 0.7: ((0.7 - 0.25) / 0.75)^1.5 exp(2 (0.49 - 1)), written out independently.
  EXPECT_NEAR(k.at(0.7), 2.0 * std::pow(0.6, 1.5) * std::exp(-1.02), 1e-14);
  EXPECT_TRUE(std::isnan(k.at(0.25)));
  const double h = 1e-6;
  EXPECT_NEAR(k.derivative(0.8), (k.at(0.8 + h) - k.at(0.8 - h)) / (2 * h), 1e-7);
}

TEST(PoroElement, RefusesBadInputNamingTheField) {
  auto expect_error = [](PoroModel m, const std::string& needle) {
    try {
      PoroSolver s(std::move(m));
      FAIL() << "accepted a model with bad " << needle;
    } catch (const PoroError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  auto m = small_model(Kinematics::plane_strain);
  m.permeability.k0_mm4_per_Ns = -1;
  expect_error(m, "k0");
  m = small_model(Kinematics::plane_strain);
  m.permeability.solid_fraction = 1.2;
  expect_error(m, "solid_fraction");
  m = small_model(Kinematics::plane_strain);
  m.skeleton.D = {};
  expect_error(m, "bulk modulus");
  m = small_model(Kinematics::plane_strain);
  m.mesh.nx = 0;
  expect_error(m, "element counts");
  m = small_model(Kinematics::axisymmetric);
  m.left.fix_x = false;
  expect_error(m, "axis");
  m = small_model(Kinematics::plane_strain);
  m.plate.enabled = true;
  expect_error(m, "plate");

  PoroSolver s(small_model(Kinematics::plane_strain));
  s.advance_to(1.0);
  EXPECT_THROW(s.advance_to(0.5), PoroError);
  EXPECT_TRUE(std::isnan(s.pressure_at(5.0, 0.5)));
}

}  // namespace
