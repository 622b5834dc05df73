#pragma once

// Plain records stored in a tocdlab measurement database (docs/database.md).
// Times: `*_t_ns` are monotonic nanoseconds (tocd::monotonic_ns(), CLOCK_MONOTONIC) and order
// everything within a run; `*_utc_ns` are wall-clock nanoseconds since the Unix epoch (UTC).
// Each run stores one (wall-clock, monotonic) anchor pair taken at the same instant, so every
// monotonic time converts to UTC unambiguously, whatever the wall clock did meanwhile.
// Physical values are SI unless the name carries the unit. An unset double is NaN (stored as
// SQL NULL); an unset id is 0.

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tocd::db {

inline constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

enum class RunStatus { running, completed, aborted, interrupted };

/// "running", "completed", "aborted", "interrupted".
std::string_view to_string(RunStatus status) noexcept;
/// Inverse of to_string; throws DatabaseError on any other text.
RunStatus run_status_from_string(std::string_view text);

/// An instrument as used in runs. (model, serial) identifies it: adding the same pair again
/// returns the existing row and updates firmware/calibration.
struct InstrumentRecord {
  std::int64_t id = 0;
  std::string kind;  // "mechanical_tester", "power_meter", "vacuum", ... (free text)
  std::string model;
  std::string serial;
  std::string firmware;
  std::string calibration;  // free text: date, certificate, coefficients
};

/// A tissue specimen.
struct SampleRecord {
  std::int64_t id = 0;
  std::string name;
  std::string tissue;  // e.g. "porcine skin, abdomen"
  double thickness_mm = kUnset;
  std::string notes;
};

/// What the caller provides to start a run (Database::create_run fills in the rest).
struct NewRun {
  std::string name;
  std::int64_t sample_id = 0;    // 0 = no specimen recorded
  std::string protocol_text;     // the protocol TOML exactly as read
  std::string lab_config_text;   // the lab TOML exactly as read
  std::string software_version;  // empty = tocd::version()
  std::string operator_name;
  double baseline_power_W = kUnset;  // glass-only power reference, when known at start
  /// Instrument settings in force for the run, e.g. "power_meter.wavelength_nm" -> "635",
  /// "power_meter.sensor" -> the sensor's identity. Stored in table run_settings.
  std::map<std::string, std::string> settings;
  /// Seconds of the run's clock per real second: 1 on a real rig; a simulated lab may run
  /// faster. Stored with each anchor so UTC stays real time (utc_ns) while the samples keep
  /// the run's own clock in t_ns.
  double clock_factor = 1.0;
};

struct RunRecord {
  std::int64_t id = 0;
  std::string uuid;  // random (version 4), unique across databases
  std::string name;
  std::int64_t sample_id = 0;
  std::string protocol_text;
  std::string lab_config_text;
  std::string software_version;
  std::string operator_name;
  double baseline_power_W = kUnset;
  std::int64_t wall_anchor_utc_ns = 0;   // wall clock at the anchor instant
  std::int64_t monotonic_anchor_ns = 0;  // monotonic clock at the same instant
  std::int64_t started_utc_ns = 0;
  std::optional<std::int64_t> ended_utc_ns;  // set when the run leaves `running`
  RunStatus status = RunStatus::running;
  std::string host;             // host name of the machine that created the run
  std::string software_commit;  // `git describe` of the build that created it ("unknown" outside git)
  std::map<std::string, std::string> settings;  // NewRun::settings
  double clock_factor = 1.0;                    // of segment 0 (NewRun::clock_factor)

  /// UTC time of a run-clock timestamp of this run by the first anchor: right only for times
  /// of segment 0 (before any resume). Use utc_ns(anchors, segment, t_ns) for any segment.
  std::int64_t to_utc_ns(std::int64_t t_ns) const noexcept {
    return wall_anchor_utc_ns + std::llround(static_cast<double>(t_ns - monotonic_anchor_ns) / clock_factor);
  }
};

/// One more (wall-clock, run-clock) anchor of a run: segment 0 is taken at create_run, one
/// more at every resume (the monotonic clock restarts at a reboot). Within a segment the
/// run's clock reads monotonic_ns at wall_utc_ns and runs clock_factor times real time.
struct RunAnchor {
  std::int64_t run_id = 0;
  int segment = 0;
  std::int64_t wall_utc_ns = 0;
  std::int64_t monotonic_ns = 0;
  double clock_factor = 1.0;
};

/// Real UTC of a run-clock time recorded in anchor segment `segment` of a run, by that
/// segment's anchor: wall + (t - monotonic) / clock_factor (the wall clock may have been
/// adjusted, the monotonic clock restarted, between segments). Falls back to the latest
/// anchor below it when `segment` is missing.
std::int64_t utc_ns(const std::vector<RunAnchor>& anchors, int segment, std::int64_t t_ns) noexcept;

/// A time series of a run: one physical quantity from one instrument.
struct Channel {
  std::int64_t id = 0;
  std::int64_t run_id = 0;
  std::string name;                // e.g. "load", "displacement", "power", "pressure"
  std::string unit;                // e.g. "N", "mm", "W", "kPa"
  std::int64_t instrument_id = 0;  // 0 = not recorded
  double nominal_rate_Hz = kUnset;
};

/// One reading. The writer stores it as (run, channel, t_ns, value, segment).
struct Sample {
  std::int64_t channel_id = 0;
  std::int64_t t_ns = 0;  // monotonic ns
  double value = 0;
  /// Anchor segment it was recorded in. Set by the database when it is written (the run's
  /// latest segment then); what a caller puts here is ignored.
  int segment = 0;
};

/// Per-channel statistics of a step's recording window.
struct ChannelStats {
  std::int64_t channel_id = 0;
  double mean = kUnset;
  double std = kUnset;  // sample standard deviation
  std::int64_t n = 0;
};

/// One protocol step. (run_id, index) identifies it: adding it again replaces the row (a
/// resumed run re-records the step that was cut short).
struct StepRecord {
  std::int64_t id = 0;
  std::int64_t run_id = 0;
  int index = 0;  // 0-based position in the protocol
  double target_displacement_mm = kUnset;
  double nominal_strain = kUnset;       // target displacement / sample thickness
  double target_pressure_kPa = kUnset;  // vacuum steps
  std::int64_t started_t_ns = 0;        // motion towards the target began
  std::int64_t settled_t_ns = 0;        // settle criterion met
  std::int64_t recorded_from_t_ns = 0;  // recording window
  std::int64_t recorded_to_t_ns = 0;
  double measured_transmission = kUnset;  // mean power / baseline power
  bool completed = true;                  // false: cut short (abort, interlock, fault)
  std::vector<ChannelStats> channels;

  const ChannelStats* stats_for(std::int64_t channel_id) const noexcept {
    for (const auto& s : channels)
      if (s.channel_id == channel_id) return &s;
    return nullptr;
  }
};

/// Something that happened during a run. Common kinds: "state" (running/paused/...),
/// "step", "fault", "retry", "interlock", "operator", "gap" (resume), "prediction".
struct EventRecord {
  std::int64_t id = 0;
  std::int64_t run_id = 0;
  std::int64_t t_ns = 0;  // monotonic ns
  std::string kind;
  std::string message;
  int step_index = -1;    // -1 = not tied to a step
  std::string data_json;  // optional machine-readable details ("" = none)
  int segment = 0;        // anchor segment; set by the database when written (as Sample)
};

/// A simulator prediction of a step's transmission.
struct PredictionRecord {
  std::int64_t id = 0;
  std::int64_t run_id = 0;
  int step_index = 0;
  std::string config_json;  // everything needed to reproduce it
  double T = kUnset;
  double T_stderr = kUnset;
  double fe_seconds = kUnset, mesh_seconds = kUnset, mc_seconds = kUnset, total_seconds = kUnset;
  /// Real (steady-clock) seconds from the moment the run's prediction queue received the
  /// recorded step (its recording had ended) to the moment this prediction was stored: what an
  /// operator waited for it, queueing behind earlier steps included. Only a run's own queue
  /// measures it; a prediction made outside a run (re-predictions, `tocdlab predict`) leaves it
  /// unset.
  double latency_s = kUnset;
  std::string software_version;     // empty = tocd::version()
  std::string summary_json;         // optional extras (FE summary, mesh stats; "" = none)
  std::int64_t created_utc_ns = 0;  // 0 = now
};

}  // namespace tocd::db
