#pragma once

#include <memory>
#include <vector>

namespace tocd::mocks {

/// What the simulated sample does under the pin: equilibrium load and optical transmission as
/// functions of the pin displacement into the sample (mm, 0 = just touching). Implementations
/// are immutable and thread-safe.
struct TissueModel {
  virtual ~TissueModel() = default;
  virtual double load_N(double displacement_mm) const = 0;  ///< equilibrium (before relaxation)
  /// Transmitted power over the source power. The source power is the glass-only reference
  /// reading, so this may exceed 1 slightly: skin in optical contact with the pin tip
  /// frustrates the total internal reflection the glass-only reference suffers there.
  virtual double transmission(double displacement_mm) const = 0;
};

/// Parameters of the analytic stand-in (docs/instruments/simulated-lab.md, "Tissue").
struct AnalyticTissueParams {
  double thickness_mm = 2.5;
  double pin_radius_mm = 1.5;
  double youngs_modulus_MPa = 0.3;  ///< small-strain modulus of the skin
  double poisson_ratio = 0.49;
  double mu_eff_per_mm = 1.0;  ///< effective attenuation of uncompressed skin
  double clearing = 0.5;       ///< fractional drop of mu_eff at full compressive log strain 1
};

/// Flat-ended cylindrical punch on a bonded, nearly incompressible layer:
///   F(d) = 2 a E/(1 - nu^2) kappa(a/h) h eps,  eps = -ln(1 - d/h) (compressive log strain),
///   kappa(x) = 1 + 1.33 x + 1.33 x^3 (finite-layer correction),
/// and a Beer-Lambert transmission through the remaining thickness with strain-dependent
/// clearing: T(d) = exp(-mu_eff (1 - clearing min(eps, 1)) (h - d)).
std::shared_ptr<TissueModel> make_analytic_tissue(double thickness_mm);
std::shared_ptr<TissueModel> make_analytic_tissue(const AnalyticTissueParams& params);

/// Piecewise-linear curves (from FE/MC runs or measurements) on increasing displacements
/// starting at 0; held constant beyond the last point. Throws ConfigError on bad tables
/// (non-finite values, transmission outside [0, 2], displacements not increasing).
std::shared_ptr<TissueModel> make_tabulated_tissue(std::vector<double> d_mm, std::vector<double> load_N,
                                                   std::vector<double> transmission);

}  // namespace tocd::mocks
