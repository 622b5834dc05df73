#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::material {

PrincipalResponse HyperelasticLaw::total(const Vec3& lambda) const {
  PrincipalResponse r = isochoric(lambda);
  const double J = lambda.prod();
  const VolumetricResponse v = volumetric(J);
  r.psi += v.U;
  // d(J U')/dx_b = J U' + J^2 U'' since dJ/dx_b = J.
  r.tau.array() += J * v.dU;
  r.dtau.array() += J * v.dU + J * J * v.d2U;
  return r;
}

VolumetricResponse abaqus_volumetric(const std::vector<double>& D, double J) {
  VolumetricResponse v;
  const double e = J - 1.0;
  // (J - 1)^(n - 2) term by term, by multiplication: std::pow of a small whole power was 8 % of
  // a plane-stress solve. Term 1 (the only one most laws have) gets e^2, e and 1, as pow gave.
  double low = 1.0;  // e^(n - 2)
  for (std::size_t i = 0; i < D.size(); ++i, low *= e * e) {
    if (D[i] == 0.0) continue;
    const int n = 2 * static_cast<int>(i + 1);
    v.U += low * (e * e) / D[i];
    v.dU += n * (low * e) / D[i];
    v.d2U += n * (n - 1) * low / D[i];
  }
  return v;
}

namespace {
// Isochoric stretches lb_a = J^(-1/3) lambda_a computed in logs for accuracy.
Vec3 isochoric_stretches(const Vec3& lambda) {
  const Vec3 x = lambda.array().log();
  const double m = x.sum() / 3.0;
  return (x.array() - m).exp();
}

double bulk_from_D(const std::vector<double>& D) {
  if (D.empty() || D[0] == 0.0) return std::numeric_limits<double>::infinity();
  return 2.0 / D[0];
}
}  // namespace

OgdenLaw::OgdenLaw(OgdenParameters p) : p_(std::move(p)) {
  p_.validate();
}

PrincipalResponse OgdenLaw::isochoric(const Vec3& lambda) const {
  // ln lb_a = ln lambda_a - (sum_b ln lambda_b) / 3, and lb_a^alpha = exp(alpha ln lb_a): Eigen's
  // pow of an array is an exact double-double algorithm, which took 60 % of an FE solve's time
  // (plane stress, whose section solves for its thickness stretch at every point, most of all).
  const Eigen::Array3d x = lambda.array().log();
  const Eigen::Array3d log_lb = x - x.sum() / 3.0;
  PrincipalResponse r;
  for (std::size_t i = 0; i < p_.mu.size(); ++i) {
    const double mu = p_.mu[i], a = p_.alpha[i];
    const Vec3 la = (a * log_lb).exp().matrix();
    const double S = la.sum();
    r.psi += 2.0 * mu / (a * a) * (S - 3.0);
    // tau_a = (2 mu / alpha) (lb_a^alpha - S/3), from d lb_b^alpha / d x_a = alpha lb_b^alpha (delta_ab -
    // 1/3).
    r.tau.array() += 2.0 * mu / a * (la.array() - S / 3.0);
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        r.dtau(k, l) += 2.0 * mu * ((k == l ? la[k] : 0.0) - (la[k] + la[l]) / 3.0 + S / 9.0);
  }
  return r;
}

VolumetricResponse OgdenLaw::volumetric(double J) const {
  return abaqus_volumetric(p_.D, J);
}

std::string OgdenLaw::describe() const {
  std::string s = fmt::format("Ogden N={}:", p_.mu.size());
  for (std::size_t i = 0; i < p_.mu.size(); ++i)
    s += fmt::format(" mu{}={:g} alpha{}={:g}", i + 1, p_.mu[i], i + 1, p_.alpha[i]);
  for (std::size_t i = 0; i < p_.D.size(); ++i) s += fmt::format(" D{}={:g}", i + 1, p_.D[i]);
  return s;
}

double OgdenLaw::shear_modulus() const {
  return p_.initial_shear_modulus();
}
double OgdenLaw::bulk_modulus() const {
  return bulk_from_D(p_.D);
}

ReducedPolynomialLaw::ReducedPolynomialLaw(std::string name, std::vector<double> c1, double c01,
                                           std::vector<double> D)
    : name_(std::move(name)), c1_(std::move(c1)), c01_(c01), D_(std::move(D)) {
  if (c1_.empty()) throw MaterialError(name_ + ": no C10 coefficient");
  for (double d : D_)
    if (!std::isfinite(d) || d < 0.0) throw MaterialError(fmt::format("{}: D = {} must be >= 0", name_, d));
  if (!(shear_modulus() > 0.0))
    throw MaterialError(
        fmt::format("{}: initial shear modulus {} MPa must be positive", name_, shear_modulus()));
}

PrincipalResponse ReducedPolynomialLaw::isochoric(const Vec3& lambda) const {
  const Vec3 lb = isochoric_stretches(lambda);
  const Vec3 l2 = lb.array().square(), lm2 = l2.cwiseInverse();
  const double I1 = l2.sum(), I2 = lm2.sum();  // I2b = sum lb^-2 because lb1 lb2 lb3 = 1
  Vec3 dI1, dI2;
  Mat3 d2I1, d2I2;
  for (int a = 0; a < 3; ++a) {
    dI1[a] = 2 * l2[a] - 2.0 / 3.0 * I1;
    dI2[a] = -2 * lm2[a] + 2.0 / 3.0 * I2;
    for (int b = 0; b < 3; ++b) {
      d2I1(a, b) = (a == b ? 4 * l2[a] : 0.0) - 4.0 / 3.0 * (l2[a] + l2[b]) + 4.0 / 9.0 * I1;
      d2I2(a, b) = (a == b ? 4 * lm2[a] : 0.0) - 4.0 / 3.0 * (lm2[a] + lm2[b]) + 4.0 / 9.0 * I2;
    }
  }
  double f = 0, df = 0, d2f = 0;
  const double e = I1 - 3.0;
  for (std::size_t k = 0; k < c1_.size(); ++k) {
    const int n = static_cast<int>(k + 1);
    f += c1_[k] * std::pow(e, n);
    df += n * c1_[k] * std::pow(e, n - 1);
    if (n >= 2) d2f += n * (n - 1) * c1_[k] * std::pow(e, n - 2);
  }
  PrincipalResponse r;
  r.psi = f + c01_ * (I2 - 3.0);
  r.tau = df * dI1 + c01_ * dI2;
  r.dtau = d2f * dI1 * dI1.transpose() + df * d2I1 + c01_ * d2I2;
  return r;
}

VolumetricResponse ReducedPolynomialLaw::volumetric(double J) const {
  return abaqus_volumetric(D_, J);
}

std::string ReducedPolynomialLaw::describe() const {
  std::string s = name_ + ":";
  for (std::size_t k = 0; k < c1_.size(); ++k) s += fmt::format(" C{}0={:g}", k + 1, c1_[k]);
  if (c01_ != 0.0) s += fmt::format(" C01={:g}", c01_);
  for (std::size_t i = 0; i < D_.size(); ++i) s += fmt::format(" D{}={:g}", i + 1, D_[i]);
  return s;
}

double ReducedPolynomialLaw::shear_modulus() const {
  return 2.0 * (c1_[0] + c01_);
}
double ReducedPolynomialLaw::bulk_modulus() const {
  return bulk_from_D(D_);
}

std::unique_ptr<HyperelasticLaw> make_ogden(const OgdenParameters& p) {
  return std::make_unique<OgdenLaw>(p);
}
std::unique_ptr<HyperelasticLaw> make_neo_hookean(double C10, double D1) {
  return std::make_unique<ReducedPolynomialLaw>("Neo-Hookean", std::vector<double>{C10}, 0.0,
                                                std::vector<double>{D1});
}
std::unique_ptr<HyperelasticLaw> make_mooney_rivlin(double C10, double C01, double D1) {
  return std::make_unique<ReducedPolynomialLaw>("Mooney-Rivlin", std::vector<double>{C10}, C01,
                                                std::vector<double>{D1});
}
std::unique_ptr<HyperelasticLaw> make_yeoh(double C10, double C20, double C30, double D1) {
  return std::make_unique<ReducedPolynomialLaw>("Yeoh", std::vector<double>{C10, C20, C30}, 0.0,
                                                std::vector<double>{D1});
}

}  // namespace tocd::sim::material
