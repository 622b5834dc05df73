#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/material/stiffness_scale.hpp"

namespace tocd::sim::material {

OgdenParameters scale_stiffness(const OgdenParameters& law, double s) {
  OgdenParameters p = law;
  for (double& mu : p.mu) mu *= s;
  for (double& d : p.D) d /= s;
  return p;
}

OgdenParameters OgdenParameters::published_skin() {
  return {{-0.24098, 0.11934, 0.12379}, {-4.3681, -3.9035, -4.7275}, {18.80, 0.0, 0.0}};
}

double OgdenParameters::initial_shear_modulus() const {
  double s = 0;
  for (double m : mu) s += m;
  return s;
}

double OgdenParameters::initial_bulk_modulus() const {
  if (D.empty() || D[0] == 0.0) return std::numeric_limits<double>::infinity();
  return 2.0 / D[0];
}

double OgdenParameters::initial_poisson_ratio() const {
  const double K = initial_bulk_modulus(), G = initial_shear_modulus();
  if (!std::isfinite(K)) return 0.5;
  return (3 * K - 2 * G) / (2 * (3 * K + G));
}

void OgdenParameters::validate() const {
  if (mu.empty()) throw MaterialError("Ogden material: no terms (mu is empty)");
  if (mu.size() != alpha.size())
    throw MaterialError(
        fmt::format("Ogden material: {} mu values but {} alpha values", mu.size(), alpha.size()));
  if (D.size() > mu.size())
    throw MaterialError(fmt::format("Ogden material: {} D values for {} terms", D.size(), mu.size()));
  for (std::size_t i = 0; i < mu.size(); ++i) {
    if (!std::isfinite(mu[i]))
      throw MaterialError(fmt::format("Ogden material: mu_{} is not a number", i + 1));
    if (!std::isfinite(alpha[i]) || alpha[i] == 0.0)
      throw MaterialError(
          fmt::format("Ogden material: alpha_{} = {} (must be finite and non-zero)", i + 1, alpha[i]));
  }
  for (std::size_t i = 0; i < D.size(); ++i)
    if (!std::isfinite(D[i]) || D[i] < 0.0)
      throw MaterialError(
          fmt::format("Ogden material: D_{} = {} (must be >= 0; 0 = term absent)", i + 1, D[i]));
  if (!(initial_shear_modulus() > 0.0))
    throw MaterialError(
        fmt::format("Ogden material: initial shear modulus sum(mu_i) = {} MPa must be positive",
                    initial_shear_modulus()));
}

}  // namespace tocd::sim::material
