#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tocd/analysis/identify_sample.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/sim/material/ogden.hpp"

namespace tocd::analysis {

/// Where the sample's own law comes from (`tocdlab compare --material`, the window's run
/// browser): fitted here to the run's load-displacement curve through the FE (model `scaled`:
/// the published shape times one stiffness factor), read from `tocdlab fit --method fe --json`,
/// or the whole identified sample (identify_sample.hpp): its stiffness, and T re-predicted
/// with its identified clearing optics and delayed clearing.
struct FittedComparisonOptions {
  std::string material = "fitted";  ///< "fitted", "identified" or the path of a fit JSON
  double pin_radius_mm = 1.5;
  std::uint64_t photons = 0;  ///< 0: each stored config's photon count ("identified": the optics')
  int threads = 0;
  /// Progress lines (the fit's iterations, each step's predictions); may be empty.
  std::function<void(const std::string&)> progress;
};

/// One step: measured load and T next to the FE force and the predicted T with the default
/// law (the stored prediction) and with the sample's law. `band_lo`/`band_hi` span T over the
/// fit's confidence laws, predicted with the same seed: the law's uncertainty, not photon
/// noise. Numbers that do not exist for a step (no stored prediction, the flat baseline's
/// force) are NaN.
struct FittedStep {
  int index = 0;
  double displacement_mm = 0, nominal_strain = 0;
  double load_N = 0, measured_T = 0;
  double fe_force_default_N = 0, fe_force_fitted_N = 0;
  double T_default = 0, T_default_se = 0;
  double T_fitted = 0, T_fitted_se = 0;
  double band_lo = 0, band_hi = 0;
};

struct FittedComparison {
  std::int64_t run_id = 0;
  sim::material::OgdenParameters law;
  /// The confidence laws that make the model band (label, law).
  std::vector<std::pair<std::string, sim::material::OgdenParameters>> band_laws;
  /// The stiffness factor and its interval when the law was fitted here (`scaled` model).
  double factor = 0, factor_low = 0, factor_high = 0, confidence = 0;
  bool fitted_here = false;
  /// "identified": the identification the steps were re-predicted from. The band of each step
  /// is then the optical parameters' 95 % band, and the law the published one times the
  /// identified stiffness scale (factor: its value and profile interval).
  std::optional<SampleIdentification> identification;
  std::vector<FittedStep> steps;
};

/// Identifies the sample's law and re-predicts every step that has a stored prediction with it
/// and with each confidence law (T relative to the run's flat baseline, as the engine does).
/// With "identified", every held step the optics were identified from gets the identification's
/// re-predicted T, stored prediction or not. Throws ConfigError for an unreadable fit file,
/// FitError when the fit fails, tocd::Error when the run cannot identify its optics, and
/// db::DatabaseError for an unknown run.
FittedComparison compare_with_fitted_law(const db::Reader& reader, std::int64_t run_id,
                                         const FittedComparisonOptions& options);

}  // namespace tocd::analysis
