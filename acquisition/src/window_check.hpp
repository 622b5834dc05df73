#pragma once

// Whether a step's recording window may stand as a measurement: every recorded channel got
// enough readings, no instrument failed during it, the pin stood where the step wants it, and
// the transmission is a real number.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tocd/core/running_stats.hpp"

namespace tocd::acquisition {

/// One recorded channel (a recorder slot) as the window check sees it.
struct WindowChannel {
  std::string_view name;  ///< "load": names it in the reasons
  double rate_Hz = 0;     ///< 0: no step depends on it, its count is not checked
};

struct WindowRequirements {
  double record_s = 0;
  std::vector<WindowChannel> channels;  ///< by recorder slot
  double min_sample_fraction = 1.0;
  std::optional<double> target_displacement_mm;  ///< pin steps
  int displacement_slot = -1;                    ///< -1: no tester
  int power_slot = -1;
  double position_tolerance_mm = 0;
  double baseline_W = 0;
};

struct WindowObservation {
  std::vector<RunningStats> stats;  ///< by recorder slot
  std::uint64_t faults = 0;         ///< instrument faults (failed reads or commands) during the window
};

/// "" when the window is a measurement, otherwise every reason it is not, joined by "; ".
std::string window_problems(const WindowRequirements& need, const WindowObservation& seen);

/// The window's statistics of `slot`; empty ones (mean NaN) for -1, a channel not recorded.
RunningStats slot_stats(const WindowObservation& seen, int slot);

}  // namespace tocd::acquisition
