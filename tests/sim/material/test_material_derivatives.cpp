// Finite-difference checks: principal stresses vs energy, principal tangent vs stresses, and the
// assembled spatial tangent vs the stress tensor (including coincident stretches).
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/material/tensor.hpp"

namespace mat = tocd::sim::material;

namespace {

std::vector<std::unique_ptr<mat::HyperelasticLaw>> laws() {
  std::vector<std::unique_ptr<mat::HyperelasticLaw>> v;
  v.push_back(mat::make_ogden(mat::OgdenParameters::published_skin()));
  v.push_back(mat::make_ogden({{0.3, -0.1}, {2.5, -3.0}, {0.5, 0.2}}));  // two volumetric terms
  v.push_back(mat::make_neo_hookean(0.1, 0.4));
  v.push_back(mat::make_mooney_rivlin(0.08, 0.02, 0.4));
  v.push_back(mat::make_yeoh(0.1, 0.03, 0.005, 0.4));
  return v;
}

// (c : d) for symmetric d, Voigt order 11 22 33 12 23 13.
mat::Mat3 contract(const mat::Mat6& c, const mat::Mat3& d) {
  const int idx[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
  mat::Mat3 out = mat::Mat3::Zero();
  for (int I = 0; I < 6; ++I) {
    double v = 0;
    for (int J = 0; J < 6; ++J) v += c(I, J) * d(idx[J][0], idx[J][1]) * (J < 3 ? 1.0 : 2.0);
    out(idx[I][0], idx[I][1]) = out(idx[I][1], idx[I][0]) = v;
  }
  return out;
}

void check_principal(const mat::HyperelasticLaw& law, const mat::Vec3& lambda) {
  const mat::PrincipalResponse r = law.total(lambda);
  const double h = 1e-6;
  for (int a = 0; a < 3; ++a) {
    mat::Vec3 xp = lambda, xm = lambda;
    xp[a] *= std::exp(h);
    xm[a] *= std::exp(-h);
    const mat::PrincipalResponse rp = law.total(xp), rm = law.total(xm);
    const double scale = law.shear_modulus() + std::abs(r.tau[a]);
    EXPECT_NEAR(r.tau[a], (rp.psi - rm.psi) / (2 * h), 1e-6 * scale) << law.describe();
    for (int b = 0; b < 3; ++b)
      EXPECT_NEAR(r.dtau(b, a), (rp.tau[b] - rm.tau[b]) / (2 * h), 1e-6 * (scale + std::abs(r.dtau(b, a))))
          << law.describe();
  }
}

// d tau along dF = H: c : sym(l) + l tau + tau l^T, l = H F^-1.
void check_spatial(const mat::HyperelasticLaw& law, const mat::Mat3& F, const char* what) {
  const mat::TensorResponse t = mat::evaluate(law, F);
  double scale = law.shear_modulus() + t.tau.norm();
  const double h = 1e-6;
  const mat::Mat3 dirs[3] = {(mat::Mat3() << 0.3, -0.2, 0.1, 0.4, -0.1, 0.2, -0.3, 0.25, 0.15).finished(),
                             (mat::Mat3() << 0, 1, 0, 0, 0, 0, 0, 0, 0).finished(),
                             (mat::Mat3() << 0, 0, 0, 0, 0, 0, 0, 0, 1).finished()};
  for (const mat::Mat3& H : dirs) {
    const mat::Mat3 dtau = (mat::evaluate(law, F + h * H).tau - mat::evaluate(law, F - h * H).tau) / (2 * h);
    const mat::Mat3 l = H * F.inverse();
    const mat::Mat3 pred = contract(t.c, 0.5 * (l + l.transpose())) + l * t.tau + t.tau * l.transpose();
    scale = std::max(scale, t.c.norm());
    EXPECT_LT((dtau - pred).norm(), 2e-6 * scale) << law.describe() << " at " << what;
    // Kirchhoff stress from the energy: tau = dW/dF F^T.
    const double dW = (mat::evaluate(law, F + h * H).psi - mat::evaluate(law, F - h * H).psi) / (2 * h);
    EXPECT_NEAR(dW, (t.tau * F.inverse().transpose()).cwiseProduct(H).sum(), 1e-6 * scale)
        << law.describe() << " at " << what;
  }
}

}  // namespace

TEST(MaterialDerivatives, PrincipalStressAndTangentMatchFiniteDifferences) {
  for (const auto& law : laws())
    for (const mat::Vec3& l : {mat::Vec3(1, 1, 1), mat::Vec3(0.6, 1.3, 1.1), mat::Vec3(0.4, 0.4, 1.7),
                               mat::Vec3(1.2, 0.7, 0.7), mat::Vec3(2.0, 0.5, 1.0)})
      check_principal(*law, l);
}

TEST(MaterialDerivatives, IsochoricPartIsPressureFree) {
  for (const auto& law : laws()) {
    const mat::PrincipalResponse r = law->isochoric(mat::Vec3(0.5, 1.4, 1.1));
    EXPECT_NEAR(r.tau.sum(), 0, 1e-12 * law->shear_modulus() * 10);
    EXPECT_LT((r.dtau * mat::Vec3::Ones()).norm(), 1e-11 * law->shear_modulus() * 10);
  }
}

TEST(MaterialDerivatives, SpatialTangentMatchesStressIncludingCoincidentStretches) {
  const mat::Mat3 I = mat::Mat3::Identity();
  mat::Mat3 general;
  general << 0.8, 0.2, 0.05, -0.1, 1.2, 0.1, 0.05, 0.15, 0.9;
  mat::Mat3 axis = mat::Mat3::Zero();  // symmetry axis: r-stretch equals hoop stretch
  axis(0, 0) = 1.3;
  axis(1, 1) = 0.55;
  axis(2, 2) = 1.3;
  mat::Mat3 hoop_equal = mat::Mat3::Zero();  // in-plane shear with the hoop stretch coinciding
  hoop_equal << 0.9, 0.3, 0, 0.3, 0.9, 0, 0, 0, 1.2;
  mat::Mat3 equal_in_plane = 0.7 * I;
  equal_in_plane(2, 2) = 1.5;
  for (const auto& law : laws()) {
    check_spatial(*law, I, "F = I");
    check_spatial(*law, 0.8 * I, "F = 0.8 I");
    check_spatial(*law, general, "general F");
    check_spatial(*law, axis, "axis (lambda_r = lambda_theta)");
    check_spatial(*law, hoop_equal, "hoop-equal");
    check_spatial(*law, equal_in_plane, "equal in-plane stretches");
  }
}

TEST(MaterialDerivatives, SmallStrainModuli) {
  const auto p = mat::OgdenParameters::published_skin();
  EXPECT_NEAR(p.initial_shear_modulus(), 0.00215, 1e-5);
  EXPECT_NEAR(p.initial_bulk_modulus(), 2 / 18.8, 1e-12);
  EXPECT_NEAR(p.initial_poisson_ratio(), 0.49, 5e-4);
  // c at F = I is the isotropic elasticity tensor: c_1111 = K + 4G/3, c_1212 = G.
  auto law = mat::make_ogden(p);
  const mat::TensorResponse t = mat::evaluate(*law, mat::Mat3::Identity());
  const double G = p.initial_shear_modulus(), K = p.initial_bulk_modulus();
  EXPECT_NEAR(t.c(0, 0), K + 4 * G / 3, 1e-9 * K);
  EXPECT_NEAR(t.c(0, 1), K - 2 * G / 3, 1e-9 * K);
  EXPECT_NEAR(t.c(3, 3), G, 1e-9 * K);
}

TEST(MaterialDerivatives, NegativeParametersAreKeptAndBadOnesRejected) {
  const auto p = mat::OgdenParameters::published_skin();
  mat::OgdenLaw law(p);
  EXPECT_LT(law.parameters().mu[0], 0);
  EXPECT_LT(law.parameters().alpha[0], 0);
  EXPECT_THROW(mat::OgdenLaw({{0.1}, {0.0}, {}}), mat::MaterialError);
  EXPECT_THROW(mat::OgdenLaw({{0.1, 0.2}, {2.0}, {}}), mat::MaterialError);
  EXPECT_THROW(mat::OgdenLaw({{0.1}, {2.0}, {-1.0}}), mat::MaterialError);
  EXPECT_THROW(mat::OgdenLaw({{-0.1}, {2.0}, {1.0}}), mat::MaterialError);
}
