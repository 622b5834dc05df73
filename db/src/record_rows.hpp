#pragma once

// What a stored row means, written once for both backends: the column lists the readers select
// and the functions that turn one row of them into a record. A Row is detail::Row (the current
// row of an SQLite statement) or pg::Row (one row of a libpq result): i64, f64, text and null
// of a column, SQL NULL read as 0, NaN and "". rows.cpp and pg/pg_rows.cpp add the WHERE and
// ORDER BY clauses in their own placeholder syntax and run the queries.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "tocd/db/database.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db::detail {

// Mixed-case column names are quoted: PostgreSQL folds unquoted names to lower case, and SQLite
// takes a quoted name that matches a column as that column.
inline constexpr const char* kRunSelect =
    "SELECT id, uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
    "\"baseline_power_W\", wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, ended_utc_ns, status, "
    "host, software_commit, "
    "coalesce((SELECT clock_factor FROM run_anchors a WHERE a.run_id = runs.id AND a.segment = 0), 1.0) "
    "FROM runs";
inline constexpr const char* kAnchorSelect =
    "SELECT segment, wall_utc_ns, monotonic_ns, clock_factor FROM run_anchors";
inline constexpr const char* kChannelSelect =
    "SELECT id, name, unit, instrument_id, \"nominal_rate_Hz\" FROM channels";
inline constexpr const char* kStepSelect =
    "SELECT id, step_index, target_displacement_mm, nominal_strain, \"target_pressure_kPa\", started_t_ns, "
    "settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed FROM steps";
/// The statistics of a run's steps, `s` the steps: callers add "WHERE s.run_id = ...".
inline constexpr const char* kStepStatsSelect =
    "SELECT x.step_id, x.channel_id, x.mean, x.std, x.n FROM step_channel_stats x "
    "JOIN steps s ON s.id = x.step_id";
inline constexpr const char* kEventSelect =
    "SELECT id, t_ns, kind, message, step_index, data_json, segment FROM events";
inline constexpr const char* kPredictionSelect =
    "SELECT id, step_index, config_json, \"T\", \"T_stderr\", fe_seconds, mesh_seconds, mc_seconds, "
    "total_seconds, software_version, summary_json, created_utc_ns, latency_s FROM predictions";
inline constexpr const char* kInstrumentSelect =
    "SELECT id, kind, model, serial, firmware, calibration FROM instruments";
inline constexpr const char* kSpecimenSelect = "SELECT id, name, tissue, thickness_mm, notes FROM specimens";

/// A row of kRunSelect; its settings are read apart.
template <class Row>
RunRecord run_from_row(const Row& row) {
  RunRecord r;
  r.id = row.i64(0);
  r.uuid = row.text(1);
  r.name = row.text(2);
  r.sample_id = row.i64(3);
  r.protocol_text = row.text(4);
  r.lab_config_text = row.text(5);
  r.software_version = row.text(6);
  r.operator_name = row.text(7);
  r.baseline_power_W = row.f64(8);
  r.wall_anchor_utc_ns = row.i64(9);
  r.monotonic_anchor_ns = row.i64(10);
  r.started_utc_ns = row.i64(11);
  if (!row.null(12)) r.ended_utc_ns = row.i64(12);
  r.status = run_status_from_string(row.text(13));
  r.host = row.text(14);
  r.software_commit = row.text(15);
  r.clock_factor = row.f64(16);
  return r;
}

/// A row of kAnchorSelect.
template <class Row>
RunAnchor anchor_from_row(const Row& row, std::int64_t run_id) {
  return {run_id, static_cast<int>(row.i64(0)), row.i64(1), row.i64(2), row.f64(3)};
}

/// A row of kChannelSelect.
template <class Row>
Channel channel_from_row(const Row& row, std::int64_t run_id) {
  return {row.i64(0), run_id, row.text(1), row.text(2), row.i64(3), row.f64(4)};
}

/// A row of kStepSelect, without its channels' statistics (add_step_stats adds them).
template <class Row>
StepRecord step_from_row(const Row& row, std::int64_t run_id) {
  StepRecord st;
  st.id = row.i64(0);
  st.run_id = run_id;
  st.index = static_cast<int>(row.i64(1));
  st.target_displacement_mm = row.f64(2);
  st.nominal_strain = row.f64(3);
  st.target_pressure_kPa = row.f64(4);
  st.started_t_ns = row.i64(5);
  st.settled_t_ns = row.i64(6);
  st.recorded_from_t_ns = row.i64(7);
  st.recorded_to_t_ns = row.i64(8);
  st.measured_transmission = row.f64(9);
  st.completed = row.i64(10) != 0;
  return st;
}

/// Where each step of `steps` stands, by step id: what add_step_stats looks the rows up in.
inline std::map<std::int64_t, std::size_t> index_by_id(const std::vector<StepRecord>& steps) {
  std::map<std::int64_t, std::size_t> by_id;
  for (std::size_t i = 0; i < steps.size(); ++i) by_id[steps[i].id] = i;
  return by_id;
}

/// Adds a row of kStepStatsSelect to its step; a row of a step not in `steps` is skipped.
template <class Row>
void add_step_stats(std::vector<StepRecord>& steps, const std::map<std::int64_t, std::size_t>& by_id,
                    const Row& row) {
  const auto it = by_id.find(row.i64(0));
  if (it != by_id.end())
    steps[it->second].channels.push_back({row.i64(1), row.f64(2), row.f64(3), row.i64(4)});
}

/// A row of kEventSelect; a NULL step index is -1 (the event belongs to no step).
template <class Row>
EventRecord event_from_row(const Row& row, std::int64_t run_id) {
  EventRecord e;
  e.id = row.i64(0);
  e.run_id = run_id;
  e.t_ns = row.i64(1);
  e.kind = row.text(2);
  e.message = row.text(3);
  e.step_index = row.null(4) ? -1 : static_cast<int>(row.i64(4));
  e.data_json = row.text(5);
  e.segment = static_cast<int>(row.i64(6));
  return e;
}

/// A row of kPredictionSelect.
template <class Row>
PredictionRecord prediction_from_row(const Row& row, std::int64_t run_id) {
  PredictionRecord p;
  p.id = row.i64(0);
  p.run_id = run_id;
  p.step_index = static_cast<int>(row.i64(1));
  p.config_json = row.text(2);
  p.T = row.f64(3);
  p.T_stderr = row.f64(4);
  p.fe_seconds = row.f64(5);
  p.mesh_seconds = row.f64(6);
  p.mc_seconds = row.f64(7);
  p.total_seconds = row.f64(8);
  p.software_version = row.text(9);
  p.summary_json = row.text(10);
  p.created_utc_ns = row.i64(11);
  p.latency_s = row.f64(12);
  return p;
}

/// A row of kInstrumentSelect.
template <class Row>
InstrumentRecord instrument_from_row(const Row& row) {
  return {row.i64(0), row.text(1), row.text(2), row.text(3), row.text(4), row.text(5)};
}

/// A row of kSpecimenSelect.
template <class Row>
SampleRecord specimen_from_row(const Row& row) {
  return {row.i64(0), row.text(1), row.text(2), row.f64(3), row.text(4)};
}

/// The run `run_id` as find_run(c, run_id) of `c`'s backend reads it; DatabaseError when the
/// store has none.
template <class Connection>
RunRecord require_run(const Connection& c, std::int64_t run_id) {
  auto r = find_run(c, run_id);
  if (!r) throw DatabaseError("no run with id " + std::to_string(run_id) + " in this database");
  return *r;
}

/// One run's rows of a record, ordered by `order_by`: `select` is the record's SELECT (kAnchorSelect
/// and the like), `from_row(row, run_id)` its reader. The backend of `c` gives read_rows and the
/// text of its first query parameter (run_id_parameter).
template <class Connection, class FromRow>
auto read_run_rows(const Connection& c, std::string_view select, std::string_view order_by,
                   std::int64_t run_id, FromRow from_row) {
  const std::string sql =
      std::string(select) + " WHERE run_id = " + run_id_parameter(c) + " ORDER BY " + std::string(order_by);
  return read_rows(c, sql, run_id, [&](const auto& row) { return from_row(row, run_id); });
}

/// The first step index not in `completed` (the completed steps' indices, ascending): where a
/// resumed run starts again.
inline int first_missing_index(const std::vector<std::int64_t>& completed) {
  int next = 0;
  for (const auto i : completed) {
    if (i == next)
      ++next;
    else if (i > next)
      break;
  }
  return next;
}

}  // namespace tocd::db::detail
