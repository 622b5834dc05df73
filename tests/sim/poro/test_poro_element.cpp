// The biphasic element's analytic tangent against central finite differences of its residual,
// and the refusal of bad input.
#include <algorithm>
#include <cmath>
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
// `stretch` < 1 first scales the element's nodes toward the origin (u = (stretch - 1) X), so
// that the volume ratio lies where the pore-closure term acts.
void expect_tangent_matches_differences(Kinematics k, double stretch = 1.0) {
  PoroSolver solver(small_model(k));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const double node_dx = 0.5, node_dy = 0.25;          // node spacing of small_model (2 x 1 mm, 2 x 2)
  const double amplitude = stretch < 1 ? 0.01 : 0.08;  // 8 %: finite strain; 1 %: stays compacted
  for (int e : {0, 3}) {
    const double x0 = (e % 2) * 2 * node_dx, y0 = (e / 2) * 2 * node_dy;
    Eigen::VectorXd x(22), prev(22);
    for (int i = 0; i < 18; ++i) {
      const int a = i / 2, li = a % 3, lj = a / 3;  // node a = 3 lj + li (grid.hpp)
      const double X = i % 2 == 0 ? x0 + li * node_dx : y0 + lj * node_dy;
      x[i] = (stretch - 1) * X + amplitude * U(rng);
      prev[i] = (stretch - 1) * X + 0.25 * amplitude * U(rng);
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

// Compacted to a volume ratio J of about 0.31 (plane strain: 0.56^2; axisymmetric: 0.68^3), a
// relative pore volume s = (J - 0.2) / 0.8 of about 0.14, below the pore-closure onset 0.2.
TEST(PoroElement, TangentMatchesFiniteDifferencesWithThePoresClosingPlaneStrain) {
  expect_tangent_matches_differences(Kinematics::plane_strain, 0.56);
}

TEST(PoroElement, TangentMatchesFiniteDifferencesWithThePoresClosingAxisymmetric) {
  expect_tangent_matches_differences(Kinematics::axisymmetric, 0.68);
}

TEST(PoroElement, PoreClosureTermActsOnlyBelowItsOnsetAndDivergesAsThePoresClose) {
  const PoreClosure c{0.2, 3.0};
  const double phi0 = 0.25, K = 2.0;  // s = (J - 0.25) / 0.75
  for (double J : {0.40, 0.5, 0.9, 1.0, 1.3}) {
    const auto v = c.at(J, phi0, K);
    EXPECT_EQ(v.U, 0.0) << J;
    EXPECT_EQ(v.dU, 0.0) << J;
    EXPECT_EQ(v.d2U, 0.0) << J;
  }
  // Onset at s = 0.2 (J = 0.4): U, U' and U'' all tend to zero there (C2 join).
  const auto near = c.at(0.4 - 1e-7, phi0, K);
  EXPECT_LT(near.U, 1e-18);
  EXPECT_LT(std::abs(near.dU), 1e-10);
  EXPECT_LT(std::abs(near.d2U), 1e-4);
  // s = 0.1 (J = 0.325): U = 3 K (-(0.1 - 0.2)^2 ln(0.5)) written out.
  EXPECT_NEAR(c.at(0.325, phi0, K).U, 3 * 2.0 * 0.01 * std::log(2.0), 1e-15);
  // Derivatives against central differences (h = 1e-6: truncation O(h^2 U''') far below).
  for (double J : {0.26, 0.3, 0.38}) {
    const double h = 1e-6;
    const auto v = c.at(J, phi0, K), p = c.at(J + h, phi0, K), m = c.at(J - h, phi0, K);
    EXPECT_NEAR(v.dU, (p.U - m.U) / (2 * h), 1e-6 * std::max(1.0, std::abs(v.dU))) << J;
    EXPECT_NEAR(v.d2U, (p.dU - m.dU) / (2 * h), 1e-6 * std::max(1.0, std::abs(v.d2U))) << J;
  }
  // As the pores close the compressive pressure -U' grows without bound; closed: no energy.
  double pressure = 0;
  for (double s : {0.15, 0.1, 0.01, 1e-4, 1e-8}) {
    const double p = -c.at(phi0 + s * (1 - phi0), phi0, K).dU;
    EXPECT_GT(p, pressure) << s;
    pressure = p;
  }
  EXPECT_GT(pressure, 1e6 * K);
  EXPECT_TRUE(std::isinf(c.at(phi0, phi0, K).U));
  EXPECT_TRUE(std::isinf(c.at(0.1, phi0, K).U));
  // Off (onset 0): nothing anywhere.
  EXPECT_EQ((PoreClosure{0.0, 3.0}.at(0.3, phi0, K).dU), 0.0);
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
  m = small_model(Kinematics::plane_strain);
  m.pore_closure.onset = 1.0;
  expect_error(m, "pore_closure onset");
  m = small_model(Kinematics::plane_strain);
  m.pore_closure.modulus_factor = 0;
  expect_error(m, "pore_closure modulus_factor");

  PoroSolver s(small_model(Kinematics::plane_strain));
  s.advance_to(1.0);
  EXPECT_THROW(s.advance_to(0.5), PoroError);
  EXPECT_TRUE(std::isnan(s.pressure_at(5.0, 0.5)));
}

}  // namespace
