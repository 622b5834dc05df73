#include "pg_rows.hpp"

#include <algorithm>
#include <map>
#include <string>

#include "pg_schema.hpp"
#include "record_rows.hpp"

namespace tocd::db::pg {

namespace {

using detail::add_step_stats;
using detail::anchor_from_row;
using detail::channel_from_row;
using detail::event_from_row;
using detail::index_by_id;
using detail::instrument_from_row;
using detail::prediction_from_row;
using detail::read_run_rows;
using detail::run_from_row;
using detail::specimen_from_row;
using detail::step_from_row;

void read_settings(const Connection& c, RunRecord& r) {
  const Result s = c.query("SELECT key, value FROM run_settings WHERE run_id = $1", {r.id});
  for (int i = 0; i < s.rows(); ++i) r.settings[s.text(i, 0)] = s.text(i, 1);
}

}  // namespace

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id) {
  auto found = read_rows(c, std::string(detail::kRunSelect) + " WHERE id = $1", run_id,
                         [](const Row& row) { return run_from_row(row); });
  if (found.empty()) return std::nullopt;
  read_settings(c, found[0]);
  return std::move(found[0]);
}

std::vector<RunRecord> all_runs(const Connection& c) {
  const Result r = c.query(std::string(detail::kRunSelect) + " ORDER BY id");
  std::vector<RunRecord> out;
  for (int i = 0; i < r.rows(); ++i) out.push_back(run_from_row(Row(r, i)));
  // All settings in one query, not one per run: each query is a round trip to the server.
  const Result s = c.query("SELECT run_id, key, value FROM run_settings ORDER BY run_id");
  std::map<std::int64_t, RunRecord*> by_id;
  for (auto& x : out) by_id[x.id] = &x;
  for (int i = 0; i < s.rows(); ++i)
    if (auto it = by_id.find(s.i64(i, 0)); it != by_id.end())
      it->second->settings[s.text(i, 1)] = s.text(i, 2);
  return out;
}

std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, detail::kAnchorSelect, "segment", run_id, anchor_from_row<Row>);
}

std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, detail::kChannelSelect, "id", run_id, channel_from_row<Row>);
}

std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id) {
  auto out = read_run_rows(c, detail::kStepSelect, "step_index", run_id, step_from_row<Row>);
  const auto by_id = index_by_id(out);
  const Result x =
      c.query(std::string(detail::kStepStatsSelect) + " WHERE s.run_id = $1 ORDER BY x.step_id, x.channel_id",
              {run_id});
  for (int i = 0; i < x.rows(); ++i) add_step_stats(out, by_id, Row(x, i));
  return out;
}

std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, detail::kEventSelect, "t_ns, id", run_id, event_from_row<Row>);
}

std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, detail::kPredictionSelect, "step_index, id", run_id, prediction_from_row<Row>);
}

std::vector<InstrumentRecord> instruments(const Connection& c) {
  const Result r = c.query(std::string(detail::kInstrumentSelect) + " ORDER BY id");
  std::vector<InstrumentRecord> out;
  for (int i = 0; i < r.rows(); ++i) out.push_back(instrument_from_row(Row(r, i)));
  return out;
}

std::optional<SampleRecord> specimen(const Connection& c, std::int64_t id) {
  auto found = read_rows(c, std::string(detail::kSpecimenSelect) + " WHERE id = $1", id,
                         [](const Row& row) { return specimen_from_row(row); });
  if (found.empty()) return std::nullopt;
  return std::move(found[0]);
}

int first_incomplete_step(const Connection& c, std::int64_t run_id) {
  return detail::first_missing_index(
      read_rows(c, "SELECT step_index FROM steps WHERE run_id = $1 AND completed <> 0 ORDER BY step_index",
                run_id, [](const Row& row) { return row.i64(0); }));
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
