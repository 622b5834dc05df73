#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/db/reader.hpp"

namespace tocd::acquisition {

/// One step of a run next to its prediction. Unset numbers are NaN.
struct CompareLine {
  int index = 0;  ///< 0-based
  bool completed = false;
  double displacement_mm = 0, nominal_strain = 0, pressure_kPa = 0;  ///< targets
  double load_N = 0;                                                 ///< mean over the recording window
  double measured_T = 0;
  bool has_prediction = false;
  double predicted_T = 0, predicted_T_stderr = 0;
  double relative_difference = 0;  ///< (predicted - measured) / measured
};

/// Measured vs. predicted transmission of a run, step by step (`tocdlab compare`, `tocdlab demo`).
struct CompareTable {
  std::int64_t run_id = 0;
  std::string run_name;
  std::string status;
  double baseline_power_W = 0;
  std::vector<CompareLine> lines;
};

/// Reads a run's steps and latest predictions. Throws db::DatabaseError for an unknown run.
CompareTable compare_table(const db::Reader& reader, std::int64_t run_id);

/// Fixed-width text table with a header, one line per step ("-" where a value is missing).
std::string format_compare_table(const CompareTable& table);

/// {"run": {...}, "steps": [{index, displacement_mm, nominal_strain, load_N, measured_T,
/// predicted_T, predicted_T_se, relative_difference}, ...]}; missing values are null.
nlohmann::json to_json(const CompareTable& table);

/// CSV with a header line (step, displacement_mm, nominal_strain, pressure_kPa, load_N,
/// measured_T, predicted_T, predicted_T_se, relative_difference, completed); empty
/// fields where a value is missing.
std::string format_compare_csv(const CompareTable& table);

}  // namespace tocd::acquisition
