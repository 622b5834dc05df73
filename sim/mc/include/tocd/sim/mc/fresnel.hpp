#pragma once

#include <cmath>

namespace tocd::sim::mc {

/// Unpolarised Fresnel reflectance for light going from index n1 into n2 with
/// cos_i = cosine of the incidence angle (0 < cos_i <= 1). Sets cos_t, the cosine of the
/// refraction angle; returns 1 (and cos_t = 0) under total internal reflection.
inline double fresnel_reflectance(double n1, double n2, double cos_i, double& cos_t) noexcept {
  if (n1 == n2) {
    cos_t = cos_i;
    return 0.0;
  }
  const double eta = n1 / n2;
  const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) {
    cos_t = 0.0;
    return 1.0;
  }
  cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace tocd::sim::mc
