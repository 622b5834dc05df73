#pragma once

// What a run was started with, fixed before its threads start and only read afterwards.

#include <cstdint>

#include "tocd/acquisition/protocol.hpp"

namespace tocd::acquisition {

struct RunSetup {
  Protocol protocol;
  std::int64_t run_id = 0;
  double baseline_W = 0;  ///< glass-only power: T = power / baseline
  int first_step = 0;     ///< 0, or the first step not recorded when the run is resumed
};

}  // namespace tocd::acquisition
