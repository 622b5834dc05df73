#include "pg_rows.hpp"

#include <algorithm>
#include <map>
#include <string>

#include "pg_schema.hpp"

namespace tocd::db::pg {

namespace {

constexpr const char* kRunColumns =
    "SELECT id, uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
    "\"baseline_power_W\", wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, ended_utc_ns, status, "
    "host, software_commit, "
    "coalesce((SELECT clock_factor FROM run_anchors a WHERE a.run_id = runs.id AND a.segment = 0), 1.0) "
    "FROM runs";

RunRecord read_run(const Result& r, int i) {
  RunRecord x;
  x.id = r.i64(i, 0);
  x.uuid = r.text(i, 1);
  x.name = r.text(i, 2);
  x.sample_id = r.i64(i, 3);
  x.protocol_text = r.text(i, 4);
  x.lab_config_text = r.text(i, 5);
  x.software_version = r.text(i, 6);
  x.operator_name = r.text(i, 7);
  x.baseline_power_W = r.f64(i, 8);
  x.wall_anchor_utc_ns = r.i64(i, 9);
  x.monotonic_anchor_ns = r.i64(i, 10);
  x.started_utc_ns = r.i64(i, 11);
  x.ended_utc_ns = r.opt_i64(i, 12);
  x.status = run_status_from_string(r.text(i, 13));
  x.host = r.text(i, 14);
  x.software_commit = r.text(i, 15);
  x.clock_factor = r.f64(i, 16);
  return x;
}

void read_settings(const Connection& c, RunRecord& r) {
  const Result s = c.query("SELECT key, value FROM run_settings WHERE run_id = $1", {r.id});
  for (int i = 0; i < s.rows(); ++i) r.settings[s.text(i, 0)] = s.text(i, 1);
}

}  // namespace

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(std::string(kRunColumns) + " WHERE id = $1", {run_id});
  if (r.rows() == 0) return std::nullopt;
  RunRecord x = read_run(r, 0);
  read_settings(c, x);
  return x;
}

std::vector<RunRecord> all_runs(const Connection& c) {
  const Result r = c.query(std::string(kRunColumns) + " ORDER BY id");
  std::vector<RunRecord> out;
  for (int i = 0; i < r.rows(); ++i) out.push_back(read_run(r, i));
  const Result s = c.query("SELECT run_id, key, value FROM run_settings ORDER BY run_id");
  std::map<std::int64_t, RunRecord*> by_id;
  for (auto& x : out) by_id[x.id] = &x;
  for (int i = 0; i < s.rows(); ++i)
    if (auto it = by_id.find(s.i64(i, 0)); it != by_id.end())
      it->second->settings[s.text(i, 1)] = s.text(i, 2);
  return out;
}

RunRecord require_run(const Connection& c, std::int64_t run_id) {
  auto r = find_run(c, run_id);
  if (!r) throw DatabaseError("no run with id " + std::to_string(run_id) + " in this database");
  return *r;
}

std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT segment, wall_utc_ns, monotonic_ns, clock_factor FROM run_anchors WHERE run_id = $1 "
      "ORDER BY segment",
      {run_id});
  std::vector<RunAnchor> out;
  for (int i = 0; i < r.rows(); ++i)
    out.push_back({run_id, static_cast<int>(r.i64(i, 0)), r.i64(i, 1), r.i64(i, 2), r.f64(i, 3)});
  return out;
}

std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT id, name, unit, instrument_id, \"nominal_rate_Hz\" FROM channels WHERE run_id = $1 ORDER BY id",
      {run_id});
  std::vector<Channel> out;
  for (int i = 0; i < r.rows(); ++i)
    out.push_back({r.i64(i, 0), run_id, r.text(i, 1), r.text(i, 2), r.i64(i, 3), r.f64(i, 4)});
  return out;
}

std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT id, step_index, target_displacement_mm, nominal_strain, \"target_pressure_kPa\", started_t_ns, "
      "settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed "
      "FROM steps WHERE run_id = $1 ORDER BY step_index",
      {run_id});
  std::vector<StepRecord> out;
  std::map<std::int64_t, std::size_t> by_id;
  for (int i = 0; i < r.rows(); ++i) {
    StepRecord st;
    st.id = r.i64(i, 0);
    st.run_id = run_id;
    st.index = static_cast<int>(r.i64(i, 1));
    st.target_displacement_mm = r.f64(i, 2);
    st.nominal_strain = r.f64(i, 3);
    st.target_pressure_kPa = r.f64(i, 4);
    st.started_t_ns = r.i64(i, 5);
    st.settled_t_ns = r.i64(i, 6);
    st.recorded_from_t_ns = r.i64(i, 7);
    st.recorded_to_t_ns = r.i64(i, 8);
    st.measured_transmission = r.f64(i, 9);
    st.completed = r.i64(i, 10) != 0;
    by_id[st.id] = out.size();
    out.push_back(std::move(st));
  }
  const Result x = c.query(
      "SELECT x.step_id, x.channel_id, x.mean, x.std, x.n FROM step_channel_stats x "
      "JOIN steps s ON s.id = x.step_id WHERE s.run_id = $1 ORDER BY x.step_id, x.channel_id",
      {run_id});
  for (int i = 0; i < x.rows(); ++i) {
    const auto it = by_id.find(x.i64(i, 0));
    if (it != by_id.end())
      out[it->second].channels.push_back({x.i64(i, 1), x.f64(i, 2), x.f64(i, 3), x.i64(i, 4)});
  }
  return out;
}

std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT id, t_ns, kind, message, step_index, data_json, segment FROM events WHERE run_id = $1 "
      "ORDER BY t_ns, id",
      {run_id});
  std::vector<EventRecord> out;
  for (int i = 0; i < r.rows(); ++i) {
    EventRecord e;
    e.id = r.i64(i, 0);
    e.run_id = run_id;
    e.t_ns = r.i64(i, 1);
    e.kind = r.text(i, 2);
    e.message = r.text(i, 3);
    e.step_index = r.null(i, 4) ? -1 : static_cast<int>(r.i64(i, 4));
    e.data_json = r.text(i, 5);
    e.segment = static_cast<int>(r.i64(i, 6));
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT id, step_index, config_json, \"T\", \"T_stderr\", fe_seconds, mesh_seconds, mc_seconds, "
      "total_seconds, software_version, summary_json, created_utc_ns FROM predictions "
      "WHERE run_id = $1 ORDER BY step_index, id",
      {run_id});
  std::vector<PredictionRecord> out;
  for (int i = 0; i < r.rows(); ++i) {
    PredictionRecord p;
    p.id = r.i64(i, 0);
    p.run_id = run_id;
    p.step_index = static_cast<int>(r.i64(i, 1));
    p.config_json = r.text(i, 2);
    p.T = r.f64(i, 3);
    p.T_stderr = r.f64(i, 4);
    p.fe_seconds = r.f64(i, 5);
    p.mesh_seconds = r.f64(i, 6);
    p.mc_seconds = r.f64(i, 7);
    p.total_seconds = r.f64(i, 8);
    p.software_version = r.text(i, 9);
    p.summary_json = r.text(i, 10);
    p.created_utc_ns = r.i64(i, 11);
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<InstrumentRecord> instruments(const Connection& c) {
  const Result r =
      c.query("SELECT id, kind, model, serial, firmware, calibration FROM instruments ORDER BY id");
  std::vector<InstrumentRecord> out;
  for (int i = 0; i < r.rows(); ++i)
    out.push_back({r.i64(i, 0), r.text(i, 1), r.text(i, 2), r.text(i, 3), r.text(i, 4), r.text(i, 5)});
  return out;
}

std::optional<SampleRecord> specimen(const Connection& c, std::int64_t id) {
  const Result r = c.query("SELECT id, name, tissue, thickness_mm, notes FROM specimens WHERE id = $1", {id});
  if (r.rows() == 0) return std::nullopt;
  return SampleRecord{r.i64(0, 0), r.text(0, 1), r.text(0, 2), r.f64(0, 3), r.text(0, 4)};
}

int first_incomplete_step(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT step_index FROM steps WHERE run_id = $1 AND completed <> 0 ORDER BY step_index", {run_id});
  int next = 0;
  for (int i = 0; i < r.rows(); ++i) {
    const auto s = r.i64(i, 0);
    if (s == next)
      ++next;
    else if (s > next)
      break;
  }
  return next;
}

std::optional<std::int64_t> last_recorded_t_ns(const Connection& c, std::int64_t run_id) {
  const Result r = c.query(
      "SELECT greatest((SELECT max((SELECT max(t_ns) FROM samples WHERE channel_id = ch.id)) FROM channels "
      "ch "
      "WHERE ch.run_id = $1), (SELECT max(t_ns) FROM events WHERE run_id = $1), "
      "(SELECT max(nullif(greatest(coalesce(recorded_to_t_ns, 0), coalesce(settled_t_ns, 0)), 0)) FROM steps "
      "WHERE run_id = $1))",
      {run_id});
  return r.opt_i64(0, 0);
}

bool run_locked(const Connection& c, std::int64_t run_id) {
  return c.query_int(
             "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND granted AND classid = "
             "$1::bigint::oid "
             "AND objid = $2::bigint::oid AND objsubid = 2",
             {kLockSpace, run_id}) > 0;
}

namespace {

constexpr const char* kRange = " channel_id = $1 AND t_ns BETWEEN $2 AND $3";

std::vector<Sample> all_samples(const Connection& c, std::int64_t channel_id, const SampleQuery& q) {
  const Result r =
      c.query(std::string("SELECT t_ns, value, segment FROM samples WHERE") + kRange + " ORDER BY t_ns",
              {channel_id, q.from_t_ns, q.to_t_ns});
  std::vector<Sample> out;
  out.reserve(static_cast<std::size_t>(r.rows()));
  for (int i = 0; i < r.rows(); ++i)
    out.push_back({channel_id, r.i64(i, 0), r.f64(i, 1), static_cast<int>(r.i64(i, 2))});
  return out;
}

}  // namespace

std::int64_t sample_count(const Connection& c, std::int64_t channel_id, const SampleQuery& q) {
  return c.query_int(std::string("SELECT count(*) FROM samples WHERE") + kRange,
                     {channel_id, q.from_t_ns, q.to_t_ns});
}

std::vector<Sample> samples(const Connection& c, std::int64_t channel_id, const SampleQuery& q) {
  if (q.decimation == Decimation::none) return all_samples(c, channel_id, q);
  const Result span =
      c.query(std::string("SELECT count(*), min(t_ns), max(t_ns) FROM samples WHERE") + kRange,
              {channel_id, q.from_t_ns, q.to_t_ns});
  const auto n = span.i64(0, 0);
  if (n <= static_cast<std::int64_t>(q.max_points)) return all_samples(c, channel_id, q);
  const std::size_t per_bucket = q.decimation == Decimation::min_max ? 2 : 1;
  const auto buckets = static_cast<std::int64_t>(std::max<std::size_t>(1, q.max_points / per_bucket));
  const std::int64_t t0 = span.i64(0, 1), t1 = span.i64(0, 2);
  const std::int64_t width = (t1 - t0) / buckets + 1;
  std::vector<Sample> out;
  if (q.decimation == Decimation::mean) {
    const Result r = c.query(
        std::string(
            "SELECT (t_ns - $4) / $5 AS b, avg(t_ns - $4)::double precision, avg(value), max(segment) "
            "FROM samples WHERE") +
            kRange + " GROUP BY b ORDER BY b",
        {channel_id, q.from_t_ns, q.to_t_ns, t0, width});
    for (int i = 0; i < r.rows(); ++i)
      out.push_back({channel_id, t0 + static_cast<std::int64_t>(r.f64(i, 1)), r.f64(i, 2),
                     static_cast<int>(r.i64(i, 3))});
    return out;
  }
  // min_max: the row of each bucket's minimum and maximum value (earliest on ties).
  const Result r = c.query(
      std::string(
          "SELECT DISTINCT ON (b, k) b, k, t_ns, value, segment FROM ("
          "SELECT (t_ns - $4) / $5 AS b, k, t_ns, value, segment FROM samples, (VALUES (0), (1)) AS kk(k) "
          "WHERE") +
          kRange + ") x ORDER BY b, k, CASE WHEN k = 0 THEN value ELSE -value END, t_ns",
      {channel_id, q.from_t_ns, q.to_t_ns, t0, width});
  for (int i = 0; i + 1 < r.rows(); i += 2) {
    Sample a{channel_id, r.i64(i, 2), r.f64(i, 3), static_cast<int>(r.i64(i, 4))};
    Sample b{channel_id, r.i64(i + 1, 2), r.f64(i + 1, 3), static_cast<int>(r.i64(i + 1, 4))};
    if (b.t_ns < a.t_ns) std::swap(a, b);
    out.push_back(a);
    if (b.t_ns != a.t_ns) out.push_back(b);
  }
  return out;
}

}  // namespace tocd::db::pg
