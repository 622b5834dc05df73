// The thickness stretch of a plane-stress point: tau_3(x_3) = 0 with the in-plane stretches
// held. A plane-stress FE section solves it at every Gauss point of every evaluation, so it is
// most of what such a section costs beyond the axisymmetric one.
#include <algorithm>
#include <array>
#include <cmath>

#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::material {

namespace {

struct ThicknessStress {
  double tau3 = 0, dtau33 = 0;  ///< tau_3 and d tau_3 / d x_3
};

/// Newton on x_3 = ln lambda_3 from the incompressible guess (J = 1); `at(x3)` gives tau_3 and
/// its slope there. Returns lambda_3, or 0 (see the header). The start matters: below J = 1/2
/// the Abaqus volumetric term's J U'(J) falls with J, so a start there finds tau_3 falling and
/// gives up on a point that has an answer. A start halfway between no thickness change and the
/// guess puts a squeezed point there (J = sqrt(lambda_1 lambda_2)); J = 1 never does.
template <class At>
double thickness_newton(double x1, double x2, At&& at) {
  double x3 = -(x1 + x2);
  for (int it = 0; it < 50; ++it) {
    const ThicknessStress s = at(x3);
    if (!(s.dtau33 > 0) || !std::isfinite(s.tau3)) return 0;
    const double dx = -s.tau3 / s.dtau33;
    x3 += std::max(-0.5, std::min(0.5, dx));
    if (std::abs(dx) < 1e-13) return std::exp(x3);
  }
  return 0;
}

/// tau_3 and its slope of the volumetric term at J: J U'(J) and J U' + J^2 U''.
ThicknessStress volumetric_part(const HyperelasticLaw& law, double J) {
  const VolumetricResponse v = law.volumetric(J);
  return {J * v.dU, J * v.dU + J * J * v.d2U};
}

}  // namespace

double HyperelasticLaw::plane_stress_stretch(double lambda1, double lambda2) const {
  return thickness_newton(std::log(lambda1), std::log(lambda2), [&](double x3) {
    const PrincipalResponse r = total(Vec3(lambda1, lambda2, std::exp(x3)));
    return ThicknessStress{r.tau[2], r.dtau(2, 2)};
  });
}

// Term i of the Ogden law with x_1, x_2 held: with s = x_1 + x_2 and m = (s + x_3) / 3, the
// isochoric stretches' powers lb_a^alpha = exp(alpha (x_a - m)) are A_1 / q, A_2 / q and A_3 q^2,
// where A_a = exp(alpha (x_a - s / 3)) (x_3 = 0 in A_3) and q = exp(alpha x_3 / 3). So each
// step costs one exponential per term: tau_3 = (2 mu / alpha)(e_3 - S / 3) and, from
// OgdenLaw::isochoric, d tau_3 / d x_3 = 2 mu (e_3 - 2 e_3 / 3 + S / 9) = 2 mu (e_3 / 3 + S / 9).
double OgdenLaw::plane_stress_stretch(double lambda1, double lambda2) const {
  constexpr std::size_t kMaxTerms = 8;  // more terms than any fit uses: the general solve
  const std::size_t n = p_.mu.size();
  if (n > kMaxTerms) return HyperelasticLaw::plane_stress_stretch(lambda1, lambda2);
  const double x1 = std::log(lambda1), x2 = std::log(lambda2), third = (x1 + x2) / 3.0;
  std::array<double, kMaxTerms> A12{}, A3{};  // A_1 + A_2, and A_3
  for (std::size_t i = 0; i < n; ++i) {
    const double a = p_.alpha[i];
    A12[i] = std::exp(a * (x1 - third)) + std::exp(a * (x2 - third));
    A3[i] = std::exp(-a * third);
  }
  return thickness_newton(x1, x2, [&](double x3) {
    ThicknessStress s = volumetric_part(*this, std::exp(x1 + x2 + x3));
    for (std::size_t i = 0; i < n; ++i) {
      const double mu = p_.mu[i], a = p_.alpha[i];
      const double q = std::exp(a * x3 / 3.0);
      const double e3 = A3[i] * q * q, S = A12[i] / q + e3;
      s.tau3 += 2.0 * mu / a * (e3 - S / 3.0);
      s.dtau33 += 2.0 * mu * (e3 / 3.0 + S / 9.0);
    }
    return s;
  });
}

}  // namespace tocd::sim::material
