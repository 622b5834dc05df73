#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {

/// One modelling choice changed from the base request.
struct SensitivityVariant {
  std::string factor;  ///< what was varied: "FE kinematics", "compressed threshold", ...
  std::string label;   ///< its value here: "plane stress", "-0.4", ...
  PredictionRequest request;
};

/// The one-at-a-time variants of a step (docs/study.md, "Sensitivity"): FE kinematics (plane
/// stress, plane strain), FE sample half width, skin bottom sliding, compressed-zone threshold
/// (-0.4, -0.6 log strain), pin length (+-0.5 mm), mesh preset (the other one), slide index
/// (1.52), graded instead of threshold optics, and one variant per law in `material_laws`
/// (e.g. InverseFitResult::confidence_laws: the ends of the fit's confidence ellipsoid's axes).
std::vector<SensitivityVariant> sensitivity_variants(
    const PredictionRequest& base,
    const std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>>& material_laws = {});

struct SensitivityRow {
  SensitivityVariant variant;
  double T = 0, T_se = 0;
  /// T(variant) - T(base) with common random numbers (same seed, photon for photon), and its
  /// standard error from the spread of the per-batch differences.
  double dT = 0, dT_se = 0;
  bool resolved = false;  ///< |dT| > 2 dT_se
  double seconds = 0;
};

struct SensitivityTable {
  PredictionRequest base;
  double T = 0, T_se = 0;  ///< of the base request
  std::vector<SensitivityRow> rows;
  /// Variants the chain could not predict (an FE that does not reach the step, an unstable
  /// law), with the reason: listed, so that a missing row is never silent.
  struct NotComputed {
    SensitivityVariant variant;
    std::string reason;
  };
  std::vector<NotComputed> not_computed;
  double seconds = 0;
};

/// Runs the base and every variant batch by batch (same seed: each batch of a variant sees the
/// same random numbers as the base's, so dT has a far smaller error than either T). A variant
/// that cannot be computed (FE does not converge, meshing fails) is reported on `progress`
/// and left out. `threads` batches run at once.
SensitivityTable run_sensitivity(Predictor& predictor, const PredictionRequest& base,
                                 const std::vector<SensitivityVariant>& variants,
                                 const std::function<void(const std::string&)>& progress = {});

std::string format_sensitivity(const SensitivityTable& table);  ///< the human table
/// One document: base T, rows {factor, label, T, T_se, dT, dT_se, resolved, config}; sorted by
/// |dT| in "tornado" (factor, label, dT, dT_se) for plotting.
nlohmann::json to_json(const SensitivityTable& table);

}  // namespace tocd::sim::study
