#pragma once

#include <memory>

#include "tocd/mocks/power_meter_twin.hpp"
#include "tocd/mocks/sim_clock.hpp"

namespace tocd::fuzz {

/// A simulated power meter whose time runs a million times faster than real time, so that a
/// zeroing or a long averaging never makes the fuzzer wait.
inline mocks::PowerMeterTwinOptions fast_meter_options() {
  mocks::PowerMeterTwinOptions o;
  o.clock = std::make_shared<mocks::SimClock>(1e6);
  return o;
}

}  // namespace tocd::fuzz
