#pragma once

#include <string>

#include <fmt/format.h>

namespace tocd::acquisition::testing {

/// A pin protocol for the fake rig (contact 1 mm, thickness 2 mm), fast settle settings.
inline std::string pin_protocol(const std::string& steps_mm, double max_load_N = 50.0, double record_s = 1.0,
                                double tester_Hz = 200.0) {
  return fmt::format(R"(name = "engine test"
[sample]
tissue = "fake skin"
thickness_mm = 2.0
[baseline]
power_W = 1.0e-3
[motion]
contact_position_mm = 1.0
approach_speed_mm_per_s = 0.5
retract_speed_mm_per_s = 2.0
[steps]
displacements_mm = [{}]
hold_s = 0.5
record_s = {}
[settle]
max_rate = 0.05
window_s = 0.5
max_wait_s = 10
[rates]
tester_Hz = {}
power_Hz = 10
pressure_Hz = 10
[interlocks]
max_load_N = {}
)",
                     steps_mm, record_s, tester_Hz, max_load_N);
}

inline std::string vacuum_protocol(const std::string& steps_kPa) {
  return fmt::format(R"(name = "vacuum test"
[sample]
tissue = "fake skin"
thickness_mm = 2.0
[baseline]
power_W = 1.0e-3
[steps]
vacuum_kPa = [{}]
hold_s = 0.5
record_s = 1.0
[settle]
max_rate = 0.5
window_s = 0.5
max_wait_s = 10
[rates]
power_Hz = 10
pressure_Hz = 20
[interlocks]
vacuum_loss_kPa = 5
)",
                     steps_kPa);
}

}  // namespace tocd::acquisition::testing
