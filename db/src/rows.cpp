#include "rows.hpp"

#include <algorithm>
#include <string>

#include "record_rows.hpp"

namespace tocd::db::detail {

namespace {

void read_settings(const Connection& c, RunRecord& r) {
  Statement s(c, "SELECT key, value FROM run_settings WHERE run_id = ?");
  s.bind(1, r.id);
  while (s.step()) r.settings[s.col_text(0)] = s.col_text(1);
}

}  // namespace

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id) {
  auto found = read_rows(c, std::string(kRunSelect) + " WHERE id = ?", run_id,
                         [](const Row& row) { return run_from_row(row); });
  if (found.empty()) return std::nullopt;
  read_settings(c, found[0]);
  return std::move(found[0]);
}

std::vector<RunRecord> all_runs(const Connection& c) {
  Statement s(c, std::string(kRunSelect) + " ORDER BY id");
  std::vector<RunRecord> out;
  while (s.step()) out.push_back(run_from_row(Row(s)));
  for (auto& r : out) read_settings(c, r);
  return out;
}

std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, kAnchorSelect, "segment", run_id, anchor_from_row<Row>);
}

std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, kChannelSelect, "id", run_id, channel_from_row<Row>);
}

std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id) {
  auto out = read_run_rows(c, kStepSelect, "step_index", run_id, step_from_row<Row>);
  const auto by_id = index_by_id(out);
  Statement stats(c, std::string(kStepStatsSelect) + " WHERE s.run_id = ? ORDER BY x.step_id, x.channel_id");
  stats.bind(1, run_id);
  while (stats.step()) add_step_stats(out, by_id, Row(stats));
  return out;
}

std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, kEventSelect, "t_ns, id", run_id, event_from_row<Row>);
}

std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id) {
  return read_run_rows(c, kPredictionSelect, "step_index, id", run_id, prediction_from_row<Row>);
}

std::vector<InstrumentRecord> instruments(const Connection& c) {
  Statement s(c, std::string(kInstrumentSelect) + " ORDER BY id");
  std::vector<InstrumentRecord> out;
  while (s.step()) out.push_back(instrument_from_row(Row(s)));
  return out;
}

std::optional<SampleRecord> specimen(const Connection& c, std::int64_t id) {
  auto found = read_rows(c, std::string(kSpecimenSelect) + " WHERE id = ?", id,
                         [](const Row& row) { return specimen_from_row(row); });
  if (found.empty()) return std::nullopt;
  return std::move(found[0]);
}

int first_incomplete_step(const Connection& c, std::int64_t run_id) {
  return first_missing_index(
      read_rows(c, "SELECT step_index FROM steps WHERE run_id = ? AND completed <> 0 ORDER BY step_index",
                run_id, [](const Row& row) { return row.i64(0); }));
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
