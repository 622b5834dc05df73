#pragma once

// A recorded run as the time histories identification works on: the tester's displacement
// and load on the run's own clock (the sample's time, sped up or not), the transmission the
// power meter saw, and the holds of the completed steps.

#include <cstdint>
#include <vector>

#include "tocd/db/reader.hpp"

namespace tocd::analysis {

/// One completed pin step's hold: from the end of the pin's move to the end of the recording
/// window, as sample indices [first, last] of RunHistory::tester_t_s.
struct Hold {
  int step_index = 0;
  double displacement_mm = 0;  ///< the tester's mean reading over the recording window
  std::size_t first = 0, last = 0;
  std::size_t record_first = 0;      ///< first sample of the recording window
  double measured_transmission = 0;  ///< the step's T as recorded (NaN without a meter)
};

struct RunHistory {
  std::int64_t run_id = 0;
  double thickness_mm = 0;
  /// Tester readings (displacement into the sample, load) at common times, in seconds of the
  /// run's clock from its anchor, ascending.
  std::vector<double> tester_t_s, displacement_mm, load_N;
  /// Transmission (power over the glass-only baseline) at the meter's reading times.
  std::vector<double> power_t_s, transmission;
  std::vector<Hold> holds;  ///< completed pin steps in contact or at contact, in order
};

/// The thickness of the sample `run` was recorded on, as the FE models it. Throws tocd::Error
/// naming the run when it has no sample record or no positive thickness.
double sample_thickness_mm(const db::Reader& reader, const db::RunRecord& run);

/// Reads run `run_id`. Throws tocd::Error naming the run when it has no tester readings, no
/// sample thickness, no completed pin step, readings of load and displacement that do not pair
/// up, or more than one clock segment (a resumed run: the history across the interruption is
/// unknown, and QLV needs all of it).
RunHistory read_run_history(const db::Reader& reader, std::int64_t run_id);

/// Linear interpolation of (x, y) at `at` (x ascending); constant beyond the ends.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at);

}  // namespace tocd::analysis
