#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {

enum class FitModel { ogden1, ogden2, ogden3, neo_hookean, mooney_rivlin, yeoh };

/// "ogden1".."ogden3", "neo-hookean", "mooney-rivlin", "yeoh"; MaterialError otherwise.
FitModel parse_fit_model(const std::string& name);
std::string to_string(FitModel m);

struct FitOptions {
  /// true: strain and stress are magnitudes of uniaxial compression (strain = displacement /
  /// thickness >= 0, stress = load / area >= 0), lambda = 1 - strain, nominal stress = -stress.
  /// false: signed nominal strain and stress (lambda = 1 + strain).
  bool compression = true;
  /// Poisson's ratio used to set D_1 from the fitted mu_0 (K_0 = 2 mu_0 (1 + nu) / (3 (1 - 2 nu)),
  /// D_1 = 2 / K_0); the curve itself is fitted incompressible, as Abaqus does. 0.5: D_1 = 0.
  double poisson_ratio = 0.49;
  int max_iterations = 400;
};

/// Drucker stability over a stretch range: the isochoric tangent d tau / d ln(lambda) must
/// be positive definite on deviatoric increments for uniaxial, equibiaxial and planar
/// deformation at every sampled stretch.
struct StabilityReport {
  bool stable = true;
  double lambda_min = 1, lambda_max = 1;  ///< range checked
  std::string first_failure;              ///< e.g. "uniaxial at lambda = 0.31"; empty if stable
};

struct FitResult {
  FitModel model = FitModel::ogden3;
  /// Model parameters by name, in model order: mu1, alpha1, ... (Ogden) or C10, C01, C20, C30.
  std::vector<std::string> names;
  std::vector<double> values;
  OgdenParameters ogden;              ///< equivalent Ogden form for Ogden, Neo-Hookean and Mooney-Rivlin
  bool has_ogden_form = false;        ///< false for Yeoh
  std::vector<double> D;              ///< D_i from FitOptions::poisson_ratio
  std::vector<double> fitted_stress;  ///< model stress at each data point (input convention)
  std::vector<double> residuals;      ///< fitted - measured [MPa]
  double rms_MPa = 0, r_squared = 0, max_abs_residual_MPa = 0;
  int iterations = 0;
  bool converged = false;
  StabilityReport stability;  ///< over the fitted stretch range
};

/// Levenberg-Marquardt least-squares fit of `model` to nominal stress-strain data in uniaxial
/// loading of an incompressible sample. Several starting points are tried for Ogden models;
/// the best is kept. Throws MaterialError on bad data (sizes, fewer points than parameters,
/// NaN, strain outside (-1, 1) or compression strain < 0).
FitResult fit_uniaxial(const std::vector<double>& strain, const std::vector<double>& stress, FitModel model,
                       const FitOptions& options = {});

/// Nominal uniaxial stress [MPa] of an incompressible Ogden sample at stretch lambda.
double ogden_uniaxial_nominal_stress(const OgdenParameters& p, double lambda);

/// Drucker check of a law between lambda_min and lambda_max (see StabilityReport).
class HyperelasticLaw;
StabilityReport check_stability(const HyperelasticLaw& law, double lambda_min, double lambda_max);

/// Two-column CSV (strain, stress); optional header line, '#' comments, ',' ';' tab or
/// space separated. Throws MaterialError naming file and line.
struct StressStrainData {
  std::vector<double> strain, stress;
};
StressStrainData read_stress_strain_csv(const std::filesystem::path& path);
StressStrainData parse_stress_strain_csv(const std::string& text, const std::string& source_name);

}  // namespace tocd::sim::material
