#pragma once

// The clearing's time course from the transmission a run recorded (no Monte Carlo): each held
// displacement's equilibrium transmission, and the delayed share of clearing with its time.
//
// Model: T(t) = (1 - f) T_e(d(t)) + f T_e(dd(t)), dd' = (d - dd) / tau_w: a share f of each
// change in transmission waits for the water to drain, following the displacement with the
// time constant tau_w (first-order drainage). T_e, the equilibrium transmission, is linear in
// d between the held displacements, whose values T_e,j are the unknowns beside f and tau_w.
// The residuals are those of the meter's readings in the holds (as for the mechanics).

#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "tocd/analysis/identified.hpp"
#include "tocd/analysis/run_history.hpp"

namespace tocd::analysis {

struct ClearingIdentification {
  /// delayed_clearing, delayed_clearing_time_s, then T_eq at each held displacement.
  ParameterReport report;
  std::vector<double> displacement_mm;  ///< the held displacements (ascending, 0 first when held)
  std::vector<double> T_eq;             ///< equilibrium transmission at each
  Eigen::MatrixXd T_eq_covariance;      ///< their covariance (as the report's intervals)
  /// Per hold: the recording window's mean of the readings and of the fitted time course, and
  /// the standard error of the measured mean (the readings' scatter over their count).
  struct Window {
    int step_index = 0;
    double displacement_mm = 0, measured = 0, fitted = 0, measured_se = 0;
    std::size_t readings = 0;
  };
  std::vector<Window> windows;
  double delayed_clearing = 0, delayed_clearing_time_s = 0;
};

/// Throws tocd::Error when the run has no transmission readings in its holds or fewer held
/// displacements than two.
ClearingIdentification identify_clearing(const RunHistory& history);

/// The fitted time course's mean over each hold's recording window with the equilibrium
/// transmissions `T_eq` (at `displacement_mm`) in place of the identified ones: what a step's
/// measured T is predicted to be from equilibrium predictions, with the identified delay.
std::vector<double> window_means(const RunHistory& history, const ClearingIdentification& clearing,
                                 const std::vector<double>& T_eq);

nlohmann::json to_json(const ClearingIdentification& c);

}  // namespace tocd::analysis
