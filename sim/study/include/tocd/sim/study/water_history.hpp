#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/poro/model.hpp"
#include "tocd/sim/study/water_optics.hpp"
#include "tocd/sim/study/water_point.hpp"

namespace tocd::sim::study {

/// A piecewise-linear pin displacement history: knots (t_s[i], d_mm[i]), t ascending from 0,
/// d >= 0 (tip depth below the undeformed top); constant after the last knot.
struct DisplacementHistory {
  std::vector<double> t_s, d_mm;
  double at(double t) const;  ///< linear between knots; d_mm[0] before the first
  /// Throws tocd::ConfigError naming what is wrong (sizes, order, negative or too deep d).
  void validate(double thickness_mm) const;
};

/// The pin follows a whole history (a recorded run: its ramps and holds, one after the other)
/// in ONE biphasic FE solve, so that the water a hold starts with is what the earlier steps
/// left; at each of `times_s` (seconds on the history's clock) the state is meshed and its
/// transmission computed with water-content optics (docs/water.md).
struct WaterHistoryRequest : WaterMcSettings {
  DisplacementHistory history;
  std::vector<double> times_s;  ///< ascending, within [0, last knot]
  double thickness_mm = 2.5, outer_radius_mm = 6.25, pin_radius_mm = 1.5;
  tocd::sim::material::OgdenParameters skeleton;  ///< empty: the published law
  double drained_poisson = 0.3;
  tocd::sim::poro::Permeability permeability{1.0, 0.25, 0.0, 0.0};
  int fe_columns = 24, fe_rows = 8;
  /// FE time steps: at most `max_step_s` long and `max_increment_mm` of pin travel each (a fast
  /// ramp is split by depth, a long hold by time), and a step ends on every knot and time point.
  double max_step_s = 2.0, max_increment_mm = 0.05;
  /// Wall-clock seconds the FE may take in all: a failing step can be halved for minutes before
  /// the solver gives up (docs/water.md, State), so the time points from there on are reported
  /// as not computed with this as the reason. <= 0: no limit.
  double fe_budget_s = 120;
  /// Called after each time point (points done, points in all); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

struct WaterHistoryPoint : WaterPointValues {
  double time_s = 0, displacement_mm = 0;
  /// false: the FE did not reach this time (or the mesh failed); `failure` says why, and the
  /// numbers of WaterPointValues are NaN.
  bool computed = false;
  std::string failure;
  int fe_step_halvings = 0;  ///< since the previous time point
};

/// Throws tocd::ConfigError naming the bad field.
void validate(const WaterHistoryRequest& r);
/// One point per time; a solver failure never throws: that point and every later one come
/// back with computed = false and the solver's message.
std::vector<WaterHistoryPoint> predict_water_history(const WaterHistoryRequest& r);
/// {time_s, displacement_mm, computed, T, T_stderr, ... | failure}; NaN as null.
nlohmann::json to_json(const WaterHistoryPoint& p);

}  // namespace tocd::sim::study
