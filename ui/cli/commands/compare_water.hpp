#pragma once

#include <cstdint>
#include <string>

#include "tocd/analysis/run_water_course.hpp"

namespace tocd::cli {

/// `tocdlab compare --optics water`: the run's recorded pin displacement through the biphasic
/// FE once, T(t) at points in each hold next to the power measured there (docs/water.md).
struct CompareWaterOptions {
  std::string db;
  std::int64_t run = 0;
  analysis::RunWaterCourseOptions course;
  bool json = false;
};

void run_compare_water(CompareWaterOptions options);

}  // namespace tocd::cli
