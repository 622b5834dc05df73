#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "tocd/sim/material/fit.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::material {

StabilityReport check_stability(const HyperelasticLaw& law, double lambda_min, double lambda_max) {
  if (!(lambda_min > 0.0) || !(lambda_max >= lambda_min))
    throw MaterialError(fmt::format("stability check: bad stretch range [{}, {}]", lambda_min, lambda_max));
  StabilityReport rep;
  rep.lambda_min = lambda_min;
  rep.lambda_max = lambda_max;
  // Orthonormal basis of deviatoric log-strain increments (sum dx_a = 0): the isochoric
  // tangent has (1,1,1) as null vector, so Drucker's dtau : deps > 0 is checked on this plane.
  Eigen::Matrix<double, 3, 2> Q;
  Q << 1 / std::sqrt(2.0), 1 / std::sqrt(6.0), -1 / std::sqrt(2.0), 1 / std::sqrt(6.0), 0,
      -2 / std::sqrt(6.0);
  const int samples = 201;
  const double l0 = std::log(lambda_min), l1 = std::log(lambda_max);
  for (int s = 0; s < samples; ++s) {
    const double lam = std::exp(l0 + (l1 - l0) * s / (samples - 1));
    const struct {
      const char* name;
      Vec3 stretch;
    } modes[] = {{"uniaxial", Vec3(lam, 1 / std::sqrt(lam), 1 / std::sqrt(lam))},
                 {"equibiaxial", Vec3(lam, lam, 1 / (lam * lam))},
                 {"planar", Vec3(lam, 1.0, 1 / lam)}};
    for (const auto& m : modes) {
      const Eigen::Matrix2d M = Q.transpose() * law.isochoric(m.stretch).dtau * Q;
      const double scale = law.shear_modulus() * 1e-9;
      if (!(M(0, 0) > scale && M.determinant() > scale * scale)) {
        rep.stable = false;
        rep.first_failure = fmt::format("{} at lambda = {:.4g}", m.name, lam);
        return rep;
      }
    }
  }
  return rep;
}

}  // namespace tocd::sim::material
