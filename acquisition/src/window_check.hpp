#pragma once

// Whether a step's recording window may stand as a measurement: every recorded channel got
// enough readings, no instrument failed during it, the pin stood where the step wants it, and
// the transmission is a real number.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "channel_slots.hpp"
#include "tocd/core/running_stats.hpp"

namespace tocd::acquisition {

struct WindowRequirements {
  double record_s = 0;
  std::array<double, kSlots> rate_Hz{};  ///< 0: the channel is not recorded
  double min_sample_fraction = 1.0;
  std::optional<double> target_displacement_mm;  ///< pin steps
  double position_tolerance_mm = 0;
  double baseline_W = 0;
};

struct WindowObservation {
  std::array<RunningStats, kSlots> stats;
  std::uint64_t faults = 0;  ///< instrument faults (failed reads or commands) during the window
};

/// "" when the window is a measurement, otherwise every reason it is not, joined by "; ".
std::string window_problems(const WindowRequirements& need, const WindowObservation& seen);

}  // namespace tocd::acquisition
