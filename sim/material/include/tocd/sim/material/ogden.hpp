#pragma once

#include <vector>

#include "tocd/core/error.hpp"

namespace tocd::sim::material {

/// Bad material parameters or data (names the parameter and the value found).
using MaterialError = tocd::ErrorOf<struct MaterialModule>;

/// Ogden hyperelastic law exactly in the Abaqus form (units MPa):
///
///   U = sum_i 2 mu_i / alpha_i^2 (lb1^alpha_i + lb2^alpha_i + lb3^alpha_i - 3)
///       + sum_i (1/D_i) (J - 1)^(2 i),          lb_k = J^(-1/3) lambda_k
///
/// N = mu.size() = alpha.size() = 1..3 (more terms are accepted too). D may be shorter than
/// N (missing entries are 0); D_i = 0 means the i-th volumetric term is absent, and all D = 0
/// means the material is treated as incompressible where that makes sense (fitting) and is
/// rejected by solvers that need a bulk modulus. mu_i and alpha_i may be negative; only
/// alpha_i = 0 is rejected. Initial shear modulus mu_0 = sum mu_i, bulk modulus K_0 = 2/D_1.
struct OgdenParameters {
  std::vector<double> mu;     ///< mu_i [MPa]
  std::vector<double> alpha;  ///< alpha_i [-]
  std::vector<double> D;      ///< D_i [1/MPa]

  /// The published porcine-skin fit (N = 3; see docs/model.md).
  static OgdenParameters published_skin();

  double initial_shear_modulus() const;  ///< sum mu_i [MPa]
  double initial_bulk_modulus() const;   ///< 2 / D_1 [MPa]; +inf when D_1 = 0
  double initial_poisson_ratio() const;  ///< (3K - 2mu) / (2 (3K + mu)); 0.5 when D_1 = 0

  /// Throws MaterialError naming the offending entry (sizes, alpha_i = 0, D_i < 0, NaN).
  void validate() const;
};

}  // namespace tocd::sim::material
