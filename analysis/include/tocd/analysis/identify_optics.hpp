#pragma once

// The clearing optics of the strain-graded model (study_optics.hpp: GradedOptics) from the
// equilibrium transmissions the clearing's time course gave (identify_clearing.hpp), on the
// geometry of each held step (the FE of the identified mechanics; the geometry of a
// displacement-driven pin does not depend on the stiffness scale, so the meshes are built
// once and reused across iterations by the predictor's caches).
//
// Parameters: the fully cleared mu_a, mu_s and n as fractions of native skin, and the
// compressive log strain of full clearing. Gauss-Newton on the generalised least squares
// (T_eq - T_MC(theta))^T (C + S)^-1 (T_eq - T_MC(theta)), C the covariance of the T_eq, S the
// Monte Carlo variances. dT/d(mu_a, mu_s) per graded level by perturbation Monte Carlo (the
// same photon histories reweighted); d/dn and d/d(full strain) by central differences with
// common random numbers. The intervals are scaled by chi^2/dof when above 1 (the model does
// not describe the sample within the errors it knows of) and use Student's t quantile.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/analysis/identified.hpp"
#include "tocd/analysis/identify_clearing.hpp"
#include "tocd/analysis/run_history.hpp"

namespace tocd::analysis {

struct OpticsOptions {
  std::uint64_t photons = 50000;  ///< per held step and evaluation
  std::uint64_t seed = 11;
  int threads = 0;  ///< Monte Carlo threads (0: all cores)
  /// Levenberg-Marquardt trials (a trial costs one Monte Carlo run per held step; an accepted
  /// one four more per step for the derivatives).
  int max_iterations = 8;
  std::string mesh_preset = "fast";
  double pin_radius_mm = 1.5;
  std::function<void(const std::string&)> progress;
};

/// The optical parameters identified: the cleared mu_a, mu_s and n fractions and the full
/// clearing strain. A run needs at least this many held displacements for them.
inline constexpr int kOpticalParameters = 4;

struct OpticsIdentification {
  /// cleared_mu_a_fraction, cleared_mu_s_fraction, cleared_n_fraction, full_clearing_strain.
  ParameterReport report;
  struct Step {
    int step_index = 0;
    double displacement_mm = 0;
    double measured_T = 0, measured_T_se = 0;    ///< the recording window's mean
    double predicted_T = 0, predicted_T_se = 0;  ///< re-predicted: identified optics and delay
    /// The 95 % band of predicted_T over the optical parameters' uncertainty: their covariance
    /// carried through the model's derivatives (linear; the Monte Carlo error is predicted_T_se).
    double band_lo = 0, band_hi = 0;
  };
  std::vector<Step> steps;
  std::vector<double> displacement_mm, T_eq, T_model, T_model_se;  ///< per held displacement
  double chi2 = 0;
  int dof = 0;
  int monte_carlo_runs = 0;
  double seconds = 0;
};

/// Throws tocd::Error when fewer held displacements than parameters are in the data.
OpticsIdentification identify_optics(const RunHistory& history, const ClearingIdentification& clearing,
                                     double stiffness_scale, const OpticsOptions& options = {});

nlohmann::json to_json(const OpticsIdentification& o);

}  // namespace tocd::analysis
