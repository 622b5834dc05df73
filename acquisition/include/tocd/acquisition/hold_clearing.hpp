#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/db/reader.hpp"

namespace tocd::acquisition {

/// How the measured transmission moved while a step held still: compression pushes water out
/// and the tissue keeps clearing during the hold. T = power / the run's baseline power, averaged
/// over the first and the last `window_s` of the step's recording window.
struct HoldClearing {
  int index = 0;  ///< 0-based
  double displacement_mm = 0;
  double window_s = 0;  ///< the recording window's length
  double T_start = 0, T_end = 0;
  double T_start_se = 0, T_end_se = 0;  ///< standard errors of the two means (sample scatter)
  double dT = 0, dT_se = 0;             ///< T_end - T_start
};

/// One entry per completed step that has power samples in both ends of its window. Throws
/// db::DatabaseError for an unknown run, tocd::Error for a run without a power channel or a
/// baseline.
std::vector<HoldClearing> hold_clearing(const db::Reader& reader, std::int64_t run_id, double window_s = 1.0);

/// Fixed-width text table with a header line.
std::string format_hold_clearing(const std::vector<HoldClearing>& rows);
/// [{step (1-based), displacement_mm, window_s, T_start, T_start_se, T_end, T_end_se, dT, dT_se}]
nlohmann::json hold_clearing_json(const std::vector<HoldClearing>& rows);

}  // namespace tocd::acquisition
