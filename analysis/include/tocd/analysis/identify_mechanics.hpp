#pragma once

// The sample's mechanics from a recorded run: quasi-linear viscoelasticity (qlv.hpp) on the
// elastic pin-compression response of the FE, identified from the whole recorded history.
//
// Model: F(t) = c + s [F_e(d(t)) + sum_i g_i h_i(t)],  h_i = integral exp(-(t-u)/tau_i) dF_e(u),
// F_e the FE's pin reaction of the published Ogden skin law at displacement d, s the
// stiffness scale (the law's shear moduli times s, D / s: the same Poisson's ratio, so the FE
// solution is the same and its load scales exactly by s), (g_i, tau_i) the Prony series and c
// the load cell's residual offset. The FE runs once, at the held displacements; F_e between
// them (on the ramps) is linear in d, which enters the overstress only at second order in the
// ramp's duration over tau. The histories run over every tester reading; the residuals are
// those of the readings in the holds (from the end of each move to the end of its recording
// window), where the load is a smooth function of time and the elastic response is the FE's
// own, not an interpolation.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/analysis/identified.hpp"
#include "tocd/analysis/run_history.hpp"

namespace tocd::analysis {

struct MechanicsOptions {
  int prony_terms = 1;  ///< 1..3
  double pin_radius_mm = 1.5;
  /// Called with a line per stage (the FE solve, the fit), from the calling thread.
  std::function<void(const std::string&)> progress;
};

/// One hold's load: measured over its recording window, and the identified model's there.
struct HoldLoad {
  int step_index = 0;
  double displacement_mm = 0;
  double elastic_N = 0;   ///< F_e of the published law at this displacement
  double measured_N = 0;  ///< mean over the recording window
  double fitted_N = 0;    ///< the identified model's mean over the same readings
  double residual_rms_N = 0;
};

struct MechanicsIdentification {
  /// load_offset_N, stiffness_scale, then g1, tau1_s, g2, tau2_s ...
  ParameterReport report;
  std::vector<HoldLoad> holds;
  double fe_seconds = 0, fit_seconds = 0;
  double thickness_mm = 0;
  /// FE of the published law at the held displacements (displacement 0 first).
  std::vector<double> fe_displacement_mm, fe_load_N;
};

/// Identifies the mechanics of `history`. Throws tocd::Error when the run holds fewer than two
/// displacements in contact, the FE fails, or the fit has fewer readings than parameters.
MechanicsIdentification identify_mechanics(const RunHistory& history, const MechanicsOptions& options = {});

/// The same on a given elastic response F_e(d) (piecewise linear through the points; for the
/// tests' closed forms and for FE responses computed elsewhere).
MechanicsIdentification identify_mechanics(const RunHistory& history, const std::vector<double>& elastic_d_mm,
                                           const std::vector<double>& elastic_load_N,
                                           const MechanicsOptions& options = {});

nlohmann::json to_json(const MechanicsIdentification& m);

}  // namespace tocd::analysis
