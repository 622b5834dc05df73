#include "rows.hpp"

#include <algorithm>
#include <map>
#include <string>

namespace tocd::db::detail {

namespace {

constexpr const char* kRunColumns =
    "SELECT id, uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
    "baseline_power_W, wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, ended_utc_ns, status, "
    "host, software_commit, "
    "coalesce((SELECT clock_factor FROM run_anchors a WHERE a.run_id = runs.id AND a.segment = 0), 1.0) "
    "FROM runs";

RunRecord read_run(const Statement& s) {
  RunRecord r;
  r.id = s.col_int(0);
  r.uuid = s.col_text(1);
  r.name = s.col_text(2);
  r.sample_id = s.col_int(3);
  r.protocol_text = s.col_text(4);
  r.lab_config_text = s.col_text(5);
  r.software_version = s.col_text(6);
  r.operator_name = s.col_text(7);
  r.baseline_power_W = s.col_double(8);
  r.wall_anchor_utc_ns = s.col_int(9);
  r.monotonic_anchor_ns = s.col_int(10);
  r.started_utc_ns = s.col_int(11);
  if (!s.col_null(12)) r.ended_utc_ns = s.col_int(12);
  r.status = run_status_from_string(s.col_text(13));
  r.host = s.col_text(14);
  r.software_commit = s.col_text(15);
  r.clock_factor = s.col_double(16);
  return r;
}

void read_settings(const Connection& c, RunRecord& r) {
  Statement s(c, "SELECT key, value FROM run_settings WHERE run_id = ?");
  s.bind(1, r.id);
  while (s.step()) r.settings[s.col_text(0)] = s.col_text(1);
}

}  // namespace

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id) {
  Statement s(c, std::string(kRunColumns) + " WHERE id = ?");
  s.bind(1, run_id);
  if (!s.step()) return std::nullopt;
  RunRecord r = read_run(s);
  read_settings(c, r);
  return r;
}

std::vector<RunRecord> all_runs(const Connection& c) {
  Statement s(c, std::string(kRunColumns) + " ORDER BY id");
  std::vector<RunRecord> out;
  while (s.step()) out.push_back(read_run(s));
  for (auto& r : out) read_settings(c, r);
  return out;
}

RunRecord require_run(const Connection& c, std::int64_t run_id) {
  auto r = find_run(c, run_id);
  if (!r) throw DatabaseError("no run with id " + std::to_string(run_id) + " in this database");
  return *r;
}

std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id) {
  Statement s(c,
              "SELECT segment, wall_utc_ns, monotonic_ns, clock_factor FROM run_anchors WHERE run_id = ? "
              "ORDER BY segment");
  s.bind(1, run_id);
  std::vector<RunAnchor> out;
  while (s.step())
    out.push_back({run_id, static_cast<int>(s.col_int(0)), s.col_int(1), s.col_int(2), s.col_double(3)});
  return out;
}

std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id) {
  Statement s(
      c, "SELECT id, name, unit, instrument_id, nominal_rate_Hz FROM channels WHERE run_id = ? ORDER BY id");
  s.bind(1, run_id);
  std::vector<Channel> out;
  while (s.step())
    out.push_back({s.col_int(0), run_id, s.col_text(1), s.col_text(2), s.col_int(3), s.col_double(4)});
  return out;
}

std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id) {
  Statement s(
      c,
      "SELECT id, step_index, target_displacement_mm, nominal_strain, target_pressure_kPa, started_t_ns, "
      "settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed "
      "FROM steps WHERE run_id = ? ORDER BY step_index");
  s.bind(1, run_id);
  std::vector<StepRecord> out;
  std::map<std::int64_t, std::size_t> by_id;
  while (s.step()) {
    StepRecord st;
    st.id = s.col_int(0);
    st.run_id = run_id;
    st.index = static_cast<int>(s.col_int(1));
    st.target_displacement_mm = s.col_double(2);
    st.nominal_strain = s.col_double(3);
    st.target_pressure_kPa = s.col_double(4);
    st.started_t_ns = s.col_int(5);
    st.settled_t_ns = s.col_int(6);
    st.recorded_from_t_ns = s.col_int(7);
    st.recorded_to_t_ns = s.col_int(8);
    st.measured_transmission = s.col_double(9);
    st.completed = s.col_int(10) != 0;
    by_id[st.id] = out.size();
    out.push_back(std::move(st));
  }
  Statement stats(c,
                  "SELECT x.step_id, x.channel_id, x.mean, x.std, x.n FROM step_channel_stats x "
                  "JOIN steps s ON s.id = x.step_id WHERE s.run_id = ? ORDER BY x.step_id, x.channel_id");
  stats.bind(1, run_id);
  while (stats.step()) {
    const auto it = by_id.find(stats.col_int(0));
    if (it == by_id.end()) continue;
    out[it->second].channels.push_back(
        {stats.col_int(1), stats.col_double(2), stats.col_double(3), stats.col_int(4)});
  }
  return out;
}

std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id) {
  Statement s(c,
              "SELECT id, t_ns, kind, message, step_index, data_json, segment FROM events WHERE run_id = ? "
              "ORDER BY t_ns, id");
  s.bind(1, run_id);
  std::vector<EventRecord> out;
  while (s.step()) {
    EventRecord e;
    e.id = s.col_int(0);
    e.run_id = run_id;
    e.t_ns = s.col_int(1);
    e.kind = s.col_text(2);
    e.message = s.col_text(3);
    e.step_index = s.col_null(4) ? -1 : static_cast<int>(s.col_int(4));
    e.data_json = s.col_text(5);
    e.segment = static_cast<int>(s.col_int(6));
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id) {
  Statement s(c,
              "SELECT id, step_index, config_json, T, T_stderr, fe_seconds, mesh_seconds, mc_seconds, "
              "total_seconds, software_version, summary_json, created_utc_ns FROM predictions "
              "WHERE run_id = ? ORDER BY step_index, id");
  s.bind(1, run_id);
  std::vector<PredictionRecord> out;
  while (s.step()) {
    PredictionRecord p;
    p.id = s.col_int(0);
    p.run_id = run_id;
    p.step_index = static_cast<int>(s.col_int(1));
    p.config_json = s.col_text(2);
    p.T = s.col_double(3);
    p.T_stderr = s.col_double(4);
    p.fe_seconds = s.col_double(5);
    p.mesh_seconds = s.col_double(6);
    p.mc_seconds = s.col_double(7);
    p.total_seconds = s.col_double(8);
    p.software_version = s.col_text(9);
    p.summary_json = s.col_text(10);
    p.created_utc_ns = s.col_int(11);
    out.push_back(std::move(p));
  }
  return out;
}

int first_incomplete_step(const Connection& c, std::int64_t run_id) {
  Statement s(c, "SELECT step_index FROM steps WHERE run_id = ? AND completed <> 0 ORDER BY step_index");
  s.bind(1, run_id);
  int next = 0;
  while (s.step()) {
    const auto i = s.col_int(0);
    if (i == next)
      ++next;
    else if (i > next)
      break;
  }
  return next;
}

std::optional<std::int64_t> last_recorded_t_ns(const Connection& c, std::int64_t run_id) {
  std::optional<std::int64_t> last;
  const auto take = [&](Statement& s) {
    while (s.step())
      if (!s.col_null(0)) last = last ? std::max(*last, s.col_int(0)) : s.col_int(0);
  };
  // Per channel, max(t_ns) is one index lookup on samples_by_channel_time.
  Statement samples(c,
                    "SELECT (SELECT max(t_ns) FROM samples WHERE channel_id = ch.id) FROM channels ch "
                    "WHERE ch.run_id = ?");
  samples.bind(1, run_id);
  take(samples);
  Statement events(c, "SELECT max(t_ns) FROM events WHERE run_id = ?");
  events.bind(1, run_id);
  take(events);
  Statement steps(
      c,
      "SELECT max(nullif(max(coalesce(recorded_to_t_ns, 0), coalesce(settled_t_ns, 0)), 0)) FROM steps "
      "WHERE run_id = ?");
  steps.bind(1, run_id);
  take(steps);
  return last;
}

}  // namespace tocd::db::detail
