#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

double Permeability::at(double J) const {
  if (!(J > solid_fraction)) return std::numeric_limits<double>::quiet_NaN();
  const double porosity_factor = (J - solid_fraction) / (1 - solid_fraction);
  return k0_mm4_per_Ns * std::pow(porosity_factor, kappa) * std::exp(0.5 * M * (J * J - 1));
}

double Permeability::derivative(double J) const {
  // d ln k / dJ = kappa / (J - phi0) + M J
  return at(J) * (kappa / (J - solid_fraction) + M * J);
}

void Permeability::validate() const {
  if (!(k0_mm4_per_Ns > 0) || !std::isfinite(k0_mm4_per_Ns))
    throw PoroError(
        fmt::format("permeability k0 must be positive and finite (got {} mm^4/(N s))", k0_mm4_per_Ns));
  if (!(solid_fraction > 0 && solid_fraction < 1))
    throw PoroError(
        fmt::format("permeability solid_fraction phi0 must lie in (0, 1) (got {})", solid_fraction));
  if (!(kappa >= 0) || !std::isfinite(kappa))
    throw PoroError(fmt::format("permeability exponent kappa must be >= 0 (got {})", kappa));
  if (!(M >= 0) || !std::isfinite(M))
    throw PoroError(fmt::format("permeability coefficient M must be >= 0 (got {})", M));
}

}  // namespace tocd::sim::poro
