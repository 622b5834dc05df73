#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tocd/core/error.hpp"

namespace tocd::acquisition {

/// A protocol file that cannot be run as written. The message starts with "<file>:<line>:"
/// and names the offending key, e.g. "demo.toml:14: [steps] hold_s: must be >= 0, got -1".
using ProtocolError = ErrorOf<struct ProtocolInput>;

/// Limits of protocol numbers that the engine and its tests rely on (docs/acquisition.md has
/// the range of every key).
namespace limits {
/// The pin travels at most this far between two tester readings (approach speed / tester_Hz).
inline constexpr double max_travel_per_poll_mm = 0.05;
inline constexpr double max_approach_speed_mm_per_s = 5.0;
inline constexpr double max_retract_speed_mm_per_s = 20.0;
inline constexpr double min_tester_Hz = 10.0;
inline constexpr double min_instrument_Hz = 1.0;  ///< power meter and vacuum controller
inline constexpr double max_load_N = 500.0;
}  // namespace limits

/// What is under the pin.
struct SampleInfo {
  std::string tissue;
  double thickness_mm = 0.0;
  std::string notes;
};

/// The glass-only power reference that turns power into transmission (T = P / P_baseline).
/// Either entered (`power_W`) or measured by the engine before the first step, averaging the
/// power meter for `measure_s` with the pin at home (the operator puts the glass-only
/// reference under the meter first).
struct Baseline {
  std::optional<double> power_W;  ///< entered value; absent when measured
  bool measure = false;
  double measure_s = 2.0;
};

/// What a step's target means.
enum class StepKind {
  displacement,  ///< pin displacement into the sample, mm (0 = contact)
  strain,        ///< nominal strain = displacement / thickness; converted to displacement
  vacuum         ///< absolute vacuum setpoint in kPa (TOCD runs; the pin is not moved)
};

std::string_view to_string(StepKind kind) noexcept;

/// When a step counts as settled: the magnitude of the load rate (N/s; kPa/s for vacuum
/// steps), fitted over the last `window_s`, drops below `max_rate`; after `max_wait_s` the
/// step goes on regardless and an event says so.
struct SettleCriterion {
  double max_rate = 0.05;
  double window_s = 1.0;
  double max_wait_s = 60.0;
};

/// One step of the protocol, already resolved to the quantity the instruments are driven by.
struct ProtocolStep {
  int index = 0;                 ///< 0-based
  double target = 0.0;           ///< as written (mm, strain or kPa)
  double displacement_mm = 0.0;  ///< pin displacement into the sample (0 for vacuum steps)
  double nominal_strain = 0.0;   ///< displacement / thickness
  double pressure_kPa = 0.0;     ///< vacuum setpoint (vacuum steps only)
};

/// Polling rates per instrument (Hz).
struct SamplingRates {
  double tester_Hz = 1000.0;  ///< position + load
  double power_Hz = 10.0;
  double pressure_Hz = 10.0;
};

/// Limits the engine enforces on every reading, independent of the instruments' own limits.
struct Interlocks {
  double max_load_N = 50.0;             ///< load above this: stop motion, retract, run interrupted
  double vacuum_loss_kPa = 5.0;         ///< pressure this far above setpoint once reached: pause
  bool power_over_range_pauses = true;  ///< a power reading flagged over-range pauses the run
  bool retract_on_trip = true;          ///< after stopping, back the pin off to home
};

/// A parsed, validated experiment protocol.
struct Protocol {
  std::string name;
  SampleInfo sample;
  Baseline baseline;
  StepKind kind = StepKind::displacement;
  std::vector<ProtocolStep> steps;
  double contact_position_mm = 0.0;      ///< tester position where the pin touches the sample
  double approach_speed_mm_per_s = 0.5;  ///< pin speed for every step move
  double retract_speed_mm_per_s = 2.0;   ///< pin speed when retracting (abort, trip, end)
  /// Zero the load cell when a pin run starts, if the pin is clear of the sample then.
  bool tare_load = true;
  /// A move the tester refuses or that fails: pause the run (false) or end it interrupted.
  bool interrupt_on_move_failure = false;
  double hold_s = 0.0;    ///< wait after settling, before recording
  double record_s = 1.0;  ///< recording window per step
  /// A pin step is recorded only when the mean displacement over its window is this close to
  /// the target (vacuum steps: EngineOptions::vacuum_reached_kPa).
  double position_tolerance_mm = 0.01;
  /// ...and every recorded channel got at least this fraction of the readings its rate
  /// promises over the window, with no instrument fault during it.
  double min_sample_fraction = 0.8;
  /// A window that fails those checks is recorded again this many times; then the step stays
  /// without a row and the run pauses.
  int max_rerecords = 2;
  SettleCriterion settle;
  SamplingRates rates;
  Interlocks interlocks;
  std::string source_text;  ///< the TOML as given (stored with the run)
  std::string source_name;

  /// Protocol duration estimate in seconds if every step settles at once (for ETA).
  double nominal_duration_s() const;
};

/// Parses and validates protocol TOML. `source_name` prefixes every error message.
Protocol parse_protocol(std::string_view toml_text, const std::string& source_name);

/// Reads and parses a protocol file.
Protocol load_protocol(const std::filesystem::path& path);

}  // namespace tocd::acquisition
