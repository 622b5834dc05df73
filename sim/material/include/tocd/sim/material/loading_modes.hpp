#pragma once

#include <string>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {

/// Homogeneous test of an incompressible sample with a closed-form nominal stress.
enum class LoadingMode {
  uniaxial,     ///< x = stretch lambda; stress = nominal (force / undeformed area)
  equibiaxial,  ///< x = in-plane stretch lambda; stress = nominal in-plane
  simple_shear  ///< x = amount of shear gamma; stress = shear force / undeformed area
};

/// "uniaxial" | "equibiaxial" | "simple-shear"; MaterialError otherwise.
LoadingMode parse_loading_mode(const std::string& name);
std::string to_string(LoadingMode mode);

/// Nominal stress [MPa] of an incompressible Ogden sample in `mode` at x (see LoadingMode).
/// Uniaxial: sum 2 mu/a (l^(a-1) - l^(-a/2-1)); equibiaxial: sum 2 mu/a (l^(a-1) - l^(-2a-1));
/// simple shear: (sigma_1 - sigma_2) / (lambda_1 + lambda_2) with the principal stretches
/// lambda_1,2 = sqrt(1 + gamma^2/4) +- gamma/2 and sigma_a = sum 2 mu/a lambda_a^a.
/// Throws MaterialError for a stretch <= 0 or a non-finite x.
double ogden_nominal_stress(const OgdenParameters& p, LoadingMode mode, double x);

}  // namespace tocd::sim::material
