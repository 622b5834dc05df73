#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/db/reader.hpp"
#include "tocd/sim/study/water_history.hpp"

namespace tocd::analysis {

/// The pin displacement a run actually went through, as the biphasic FE takes it.
struct RunDisplacementHistory {
  std::int64_t t0_ns = 0;  ///< time zero of `history`: the first displacement sample
  /// Knots chosen among the recorded samples so that the piecewise-linear curve through them
  /// stays within `tolerance_mm` of every sample (the recorded channel runs at 1 kHz; the FE
  /// needs its corners, not every reading). Depths above the surface (< 0) are 0: the pin does
  /// not touch the skin there.
  sim::study::DisplacementHistory history;
  std::size_t samples = 0;  ///< recorded samples it stands for
  double tolerance_mm = 0;
};

/// The run's displacement channel from its first sample to `until_ns` (inclusive). Throws
/// tocd::Error for a run without a displacement channel or samples, one that starts with the
/// pin already in the skin (the FE starts from the undeformed state), or a resumed run.
RunDisplacementHistory displacement_history_from_run(const db::Reader& reader, std::int64_t run_id,
                                                     std::int64_t until_ns, double tolerance_mm = 1e-3);

/// Measured T = mean power / the run's baseline power over [from_ns, to_ns] (both inclusive),
/// with the standard error of the mean from the sample scatter; n = 0 and NaN when empty.
struct MeasuredT {
  double T = 0, se = 0;
  std::int64_t n = 0;
};
MeasuredT measured_T_between(const db::Reader& reader, std::int64_t power_channel, double baseline_power_W,
                             std::int64_t from_ns, std::int64_t to_ns);

struct RunWaterCourseOptions {
  /// Time points per step's recording window, evenly spaced from `window_s`/2 after its start
  /// to `window_s`/2 before its end (one, the middle, when the recording window is shorter than
  /// two averaging windows).
  int points_per_hold = 3;
  double window_s = 1.0;  ///< the measured T at a point is averaged over this, centred on it
  double pin_radius_mm = 1.5;
  double tolerance_mm = 1e-3;  ///< of the displacement history
  double drained_poisson = 0.3, k0_mm4_per_Ns = 1.0;
  double fe_budget_s = 120;  ///< see WaterHistoryRequest::fe_budget_s
  std::uint64_t photons = 20000, seed = 1;
  int threads = 0;
  std::string mesh_preset = "fast";
  /// Progress lines (history, baseline, each time point); may be empty.
  std::function<void(const std::string&)> progress;
  /// After each predicted time point (done, in all); may be empty.
  std::function<void(std::size_t, std::size_t)> point_progress;
};

struct WaterCoursePoint {
  double t_s = 0;         ///< on the history's clock (since the first displacement sample)
  double t_window_s = 0;  ///< since the start of the step's recording window
  MeasuredT measured;
  /// The water-graded prediction at t_s as the solver gave it: the pin's displacement, whether
  /// it was computed (false: `failure` says why and its numbers are NaN), the absolute T, the
  /// pin's force, the water pushed out, and the wall seconds of the FE since the previous
  /// point, this point's composite mesh and its Monte Carlo.
  sim::study::WaterHistoryPoint predicted;
  double T = 0, T_se = 0;  ///< predicted.T / T(glass-only baseline), as the engine's predictions
};

struct WaterCourseStep {
  int index = 0;  ///< 0-based
  double target_displacement_mm = 0;
  double window_from_s = 0, window_to_s = 0;  ///< recording window on the history's clock
  std::vector<WaterCoursePoint> points;
};

struct RunWaterCourse {
  std::int64_t run_id = 0;
  double thickness_mm = 0;
  RunDisplacementHistory history;
  double baseline_T = 0, baseline_T_se = 0;  ///< the glass-only Monte Carlo T
  RunWaterCourseOptions options;
  std::vector<WaterCourseStep> steps;
  double seconds = 0;  ///< wall time of the whole computation
};

/// Drives the biphasic pin problem along the run's recorded displacement once and predicts T
/// at points inside every completed step's recording window, next to the measured T there.
/// Throws db::DatabaseError for an unknown run, tocd::Error for a run without a power channel,
/// a baseline power, a sample thickness or a displacement record, and ConfigError for bad
/// options. A solver failure is not thrown: the points from there on are not computed.
RunWaterCourse run_water_course(const db::Reader& reader, std::int64_t run_id,
                                const RunWaterCourseOptions& o);

/// Fixed-width text: a header, then one line per step and time point.
std::string format_run_water_course(const RunWaterCourse& c);
/// {"run", "config", "history", "baseline", "steps": [{step, displacement_mm, window_s: [from, to],
/// points: [{t_s, t_window_s, displacement_mm, measured_T, measured_T_se, measured_samples,
/// computed, predicted_T, predicted_T_se, pin_force_N, water_outflow_mm3 | failure, fe_seconds,
/// mesh_seconds, mc_seconds}]}]}; NaN as null.
nlohmann::json to_json(const RunWaterCourse& c);

}  // namespace tocd::analysis
