#pragma once

#include <cmath>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::poro::reference {

/// A one-term Ogden (alpha = 2: neo-Hookean) skeleton with small-strain shear modulus mu and
/// drained Poisson's ratio nu: K = 2 mu (1 + nu) / (3 (1 - 2 nu)), D_1 = 2 / K.
inline tocd::sim::material::OgdenParameters skeleton(double mu, double nu) {
  const double K = 2 * mu * (1 + nu) / (3 * (1 - 2 * nu));
  return {{mu}, {2.0}, {2.0 / K}};
}

/// Drained constrained (oedometric) modulus K + 4/3 mu.
inline double constrained_modulus(double mu, double nu) {
  return 2 * mu * (1 + nu) / (3 * (1 - 2 * nu)) + 4.0 / 3.0 * mu;
}

}  // namespace tocd::sim::poro::reference
