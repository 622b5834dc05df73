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

/// A compression step followed by a hold, with water (docs/water.md): the pin is pushed to
/// `displacement_mm` over `ramp_s`, then held; at each of `times_s` (seconds since the start
/// of the hold) the biphasic FE state is meshed and its transmission computed with
/// water-content optics.
struct WaterTimeCourseRequest : WaterMcSettings {
  /// Defaults: a depth and a compressible skeleton (drained Poisson's ratio 0.3) at which water
  /// leaves and T rises over the hold beyond its Monte Carlo error; measured to converge
  /// through the ramp and the 60 s hold (docs/water.md, State).
  double displacement_mm = 1.25, thickness_mm = 2.5, outer_radius_mm = 6.25, pin_radius_mm = 1.5;
  double ramp_s = 30.0;
  std::vector<double> times_s = {0, 10, 30, 60};
  /// Skeleton: the published Ogden mu_i, alpha_i with a drained Poisson's ratio (D_1 from it).
  tocd::sim::material::OgdenParameters skeleton;
  double drained_poisson = 0.3;
  tocd::sim::poro::Permeability permeability{1.0, 0.25, 0.0, 0.0};
  int fe_columns = 24, fe_rows = 8, steps_per_interval = 1;
  /// Called after each time point (points done, points in all); may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

struct WaterTimePoint : WaterPointValues {
  double time_s = 0;  ///< since the start of the hold
};

/// Throws tocd::ConfigError naming the bad field.
void validate(const WaterTimeCourseRequest& r);
std::vector<WaterTimePoint> predict_water_time_course(const WaterTimeCourseRequest& r);
nlohmann::json to_json(const WaterTimePoint& p);

}  // namespace tocd::sim::study
