#pragma once

#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

namespace tocd::sim::study {

/// What a water-graded prediction gives at one time, whichever loading led there (a ramp and
/// hold, or a recorded displacement history): its T, the pin's force and the water pushed out
/// in the FE state, the tets per water level of its mesh, and the seconds each stage took.
struct WaterPointValues {
  double T = 0, T_stderr = 0;
  double pin_force_N = 0, water_outflow_mm3 = 0;
  std::vector<std::size_t> tets_per_level;
  double fe_seconds = 0, mesh_seconds = 0, mc_seconds = 0;
};

/// Adds the fields of `v` to the object `j` under their own names (a number that is not
/// finite as null).
void add_to_json(nlohmann::json& j, const WaterPointValues& v);

}  // namespace tocd::sim::study
