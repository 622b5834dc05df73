#pragma once

#include <vector>

#include "tocd/sim/study/water_time_course.hpp"

namespace tocd::cli {

/// `tocdlab predict --optics water`: T(t) over one hold with the biphasic FE and water-content
/// optics (docs/water.md, "Time course of a hold").
struct PredictWaterOptions {
  sim::study::WaterTimeCourseRequest request;
  double hold_s = 60;
  std::vector<double> times_s;  ///< explicit time points; empty: 0, hold/6, hold/2, hold
  bool json = false;
};

void run_predict_water(PredictWaterOptions options);

}  // namespace tocd::cli
