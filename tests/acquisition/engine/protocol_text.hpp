#pragma once

// The engine tests' protocols for the fake rig (contact 1 mm, thickness 2 mm, fast settle).

#include <string>

#include "tocd/test/protocol_text.hpp"

namespace tocd::acquisition::testing {

inline std::string pin_protocol(const std::string& steps_mm, double max_load_N = 50.0, double record_s = 1.0,
                                double tester_Hz = 200.0) {
  tocd::test::PinProtocolText p;
  p.name = "engine test";
  p.tissue = "fake skin";
  p.thickness_mm = 2.0;
  p.approach_speed_mm_per_s = 0.5;
  p.retract_speed_mm_per_s = 2.0;
  p.displacements_mm = steps_mm;
  p.record_s = record_s;
  p.settle->max_wait_s = 10;
  p.tester_Hz = tester_Hz;
  p.power_Hz = 10;
  p.pressure_Hz = 10;
  p.max_load_N = max_load_N;
  return tocd::test::protocol_toml(p);
}

inline std::string vacuum_protocol(const std::string& steps_kPa) {
  tocd::test::VacuumProtocolText p;
  p.tissue = "fake skin";
  p.vacuum_kPa = steps_kPa;
  return tocd::test::protocol_toml(p);
}

}  // namespace tocd::acquisition::testing
