#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/material/fit.hpp"
#include "tocd/sim/material/loading_modes.hpp"

namespace tocd::sim::fe {

/// A recorded pin-compression curve and the FE model of its sample (thickness, pin radius,
/// kinematics, mesh; the material is what the fit sets).
struct PinCompressionData {
  std::string name = "pin compression";
  FeModel model = FeModel::published_default();
  std::vector<double> displacement_mm, load_N;  ///< ascending displacements > 0
  double weight = 1;                            ///< multiplies the squared relative residuals
};

/// A homogeneous test with a closed-form stress (uniaxial, equibiaxial, simple shear).
struct ClosedFormData {
  std::string name;
  tocd::sim::material::LoadingMode mode = tocd::sim::material::LoadingMode::uniaxial;
  std::vector<double> x;           ///< stretch (uniaxial, equibiaxial) or amount of shear
  std::vector<double> stress_MPa;  ///< nominal, signed (compression negative)
  double weight = 1;
};

/// Which parameters are free.
enum class InverseModel {
  scaled,  ///< the reference law's shape, one stiffness factor s: mu_i -> s mu_i, D_i -> D_i / s
  ogden1,
  ogden2,
  ogden3  ///< mu_i, alpha_i free (D_1 from the Poisson's ratio unless fit_D)
};
InverseModel parse_inverse_model(const std::string& name);  ///< "scaled" | "ogden1..3"; MaterialError
std::string to_string(InverseModel m);
/// How many parameters a fit of `m` adjusts (D_1 among them when `fit_D`).
std::size_t free_parameters(InverseModel m, bool fit_D);

struct InverseFitOptions {
  InverseModel model = InverseModel::ogden3;
  /// Shape of `scaled` and the start of the Ogden fits (scaled to the data first).
  tocd::sim::material::OgdenParameters reference = tocd::sim::material::OgdenParameters::published_skin();
  bool fit_D = false;           ///< D_1 a free parameter too
  double poisson_ratio = 0.49;  ///< sets D_1 = 3 (1 - 2 nu) / (mu_0 (1 + nu)) when D_1 is not free
  /// Residuals are relative: (model - data) / max(|data|, floor x the dataset's largest |data|),
  /// so small loads near first contact do not vanish from the fit nor dominate it.
  double relative_floor = 0.02;
  int max_iterations = 30;
  double confidence = 0.95;
  std::function<void(const std::string&)> progress;  ///< one line per accepted step
};

struct DatasetFit {
  std::string name;
  std::vector<double> x, measured, fitted;        ///< x: displacement [mm] or stretch/shear; N or MPa
  double rms_relative = 0, max_abs_relative = 0;  ///< of (fitted - measured) / max(|measured|, floor)
};

struct InverseFitResult {
  InverseModel model = InverseModel::ogden3;
  tocd::sim::material::OgdenParameters material;  ///< the fitted law (D_1 set)
  std::vector<std::string> names;                 ///< mu1, alpha1, ..., [D1] or s
  std::vector<double> values, standard_errors, interval_low, interval_high;
  std::vector<std::vector<double>> covariance;
  double confidence = 0.95, residual_variance = 0, t_quantile = 0;
  std::vector<DatasetFit> datasets;
  int iterations = 0, evaluations = 0;
  bool converged = false;
  std::string stop_reason;
  /// Drucker stability of the fitted law: over [0.15, 1/0.15] and, if it fails there, the
  /// widest stable stretch interval around 1 found by halving (stable_lambda_min/max).
  tocd::sim::material::StabilityReport stability;
  double stable_lambda_min = 0, stable_lambda_max = 0;
  /// Laws at the ends of the principal axes of the confidence ellipsoid (theta +- t sqrt(l_k) v_k
  /// for each eigenpair (l_k, v_k) of the covariance), for uncertainty bands of predictions;
  /// axes the data do not identify are left out. Labels "axis 1 -", "axis 1 +", ...
  std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>> confidence_laws;
  double poisson_ratio = 0.49;  ///< the one D_1 followed (when not fitted)
};

/// Fits the law to every dataset at once (least squares on weighted relative residuals,
/// Levenberg-Marquardt with the FE in the loop: one incremental solve per evaluation gives the
/// whole force curve). Confidence intervals from s^2 (J^T J)^-1 and Student's t. Throws
/// material::MaterialError / FeError on bad data (no datasets, unordered displacements,
/// sizes, NaN) or a start the FE cannot solve.
InverseFitResult fit_material(const std::vector<PinCompressionData>& pins,
                              const std::vector<ClosedFormData>& closed_forms,
                              const InverseFitOptions& options = {});

/// The FE force curve of one dataset's model with `material` at its displacements; empty when
/// the solve stopped early.
std::vector<double> pin_force_curve(const PinCompressionData& data,
                                    const tocd::sim::material::OgdenParameters& material);

nlohmann::json to_json(const InverseFitResult& result);

/// A law's Drucker stability as the fits' JSON writes it: stable, lambda_min, lambda_max,
/// first_failure (here, beside the fits' JSON: sim/material has no JSON).
nlohmann::json to_json(const tocd::sim::material::StabilityReport& stability);

/// What a fit's JSON (to_json, `tocdlab fit --method fe --json`) gives its readers: the fitted
/// law and the laws at the ends of its confidence-ellipsoid axes, each validated. Throws
/// nlohmann::json::exception for a missing or mistyped key, MaterialError for a bad law.
struct FittedLaws {
  tocd::sim::material::OgdenParameters law;
  std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>> confidence_laws;
};
FittedLaws fitted_laws_from_json(const nlohmann::json& fit);

}  // namespace tocd::sim::fe
