#pragma once
// The steady clock the study's results are timed with (fe_seconds, mc seconds, the FE budget).

#include <chrono>

namespace tocd::sim::study {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since t0 on the steady clock.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace tocd::sim::study
