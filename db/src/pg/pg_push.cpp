#include <map>
#include <string>

#include <fmt/format.h>

#include "pg_schema.hpp"
#include "pg_util.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/enum_names.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/push.hpp"
#include "tocd/db/reader.hpp"

namespace tocd::db {

namespace {
constexpr std::array<EnumName<PushAction>, 4> kPushActionNames{{{PushAction::copied, "copied"},
                                                                {PushAction::updated, "updated"},
                                                                {PushAction::unchanged, "unchanged"},
                                                                {PushAction::skipped, "skipped"}}};
}  // namespace

std::string_view to_string(PushAction action) noexcept {
  return name_of(kPushActionNames, action);
}

namespace {

// Everything of one run, read from the file before the server is touched: the digest and the
// copy describe the same state.
struct RunCopy {
  RunRecord run;
  std::optional<SampleRecord> specimen;
  std::map<std::int64_t, InstrumentRecord> instruments;  // by local id
  std::vector<RunAnchor> anchors;
  std::vector<Channel> channels;
  std::vector<std::vector<Sample>> samples;  // per channel, as channels
  std::vector<StepRecord> steps;
  std::vector<EventRecord> events;
  std::vector<PredictionRecord> predictions;
  std::int64_t sample_count = 0;

  // What decides whether the server's copy is current: a resume adds an anchor and events,
  // the end sets the status and the end time, a late prediction adds a row.
  std::string digest() const {
    std::int64_t last_t = 0;
    for (const auto& ch : samples)
      if (!ch.empty()) last_t = std::max(last_t, ch.back().t_ns);
    return fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", to_string(run.status), run.ended_utc_ns.value_or(-1),
                       run.baseline_power_W, anchors.size(), channels.size(), sample_count, last_t,
                       steps.size(), events.size(), predictions.size());
  }
};

RunCopy read_run(const Reader& r, const RunSummary& s) {
  RunCopy c;
  c.run = s.run;
  c.run.status = shown_status(s);
  if (c.run.sample_id != 0) c.specimen = r.sample(c.run.sample_id);
  c.anchors = r.anchors(s.run.id);
  c.channels = r.channels(s.run.id);
  for (const auto& ch : c.channels) {
    c.samples.push_back(r.samples(ch.id));
    c.sample_count += static_cast<std::int64_t>(c.samples.back().size());
    if (ch.instrument_id != 0 && !c.instruments.count(ch.instrument_id))
      if (auto in = r.instrument(ch.instrument_id)) c.instruments[ch.instrument_id] = *in;
  }
  c.steps = r.steps(s.run.id);
  c.events = r.events(s.run.id);
  c.predictions = r.predictions(s.run.id);
  return c;
}

using pg::Param;

// Removes what the server holds of a run (not the run row itself, which keeps its id).
void clear_run(const pg::Connection& c, std::int64_t id) {
  c.query("DELETE FROM samples WHERE channel_id IN (SELECT id FROM channels WHERE run_id = $1)", {id});
  c.query("DELETE FROM steps WHERE run_id = $1", {id});  // statistics cascade
  for (const char* table : {"events", "predictions", "channels", "run_anchors", "run_settings"})
    c.query(fmt::format("DELETE FROM {} WHERE run_id = $1", table), {id});
}

std::int64_t server_specimen(const pg::Connection& c, const SampleRecord& sp) {
  // Runs of one specimen share its row on the server too.
  const auto found = c.query_int(
      "SELECT id FROM specimens WHERE name = $1 AND tissue = $2 AND thickness_mm IS NOT DISTINCT FROM "
      "$3::double precision AND notes = $4 ORDER BY id LIMIT 1",
      {sp.name, sp.tissue, sp.thickness_mm, sp.notes});
  if (found != 0) return found;
  return c.query_int(
      "INSERT INTO specimens(name, tissue, thickness_mm, notes) VALUES($1,$2,$3,$4) RETURNING id",
      {sp.name, sp.tissue, sp.thickness_mm, sp.notes});
}

void write_run_rows(const pg::Connection& c, const RunCopy& rc, std::int64_t id) {
  const RunRecord& r = rc.run;
  for (const auto& [key, value] : r.settings)
    c.query("INSERT INTO run_settings(run_id, key, value) VALUES($1,$2,$3)", {id, key, value});
  for (const auto& a : rc.anchors)
    c.query(
        "INSERT INTO run_anchors(run_id, segment, wall_utc_ns, monotonic_ns, clock_factor) "
        "VALUES($1,$2,$3,$4,$5)",
        {id, a.segment, a.wall_utc_ns, a.monotonic_ns, a.clock_factor});
  std::map<std::int64_t, std::int64_t> instrument;
  for (const auto& [local, in] : rc.instruments)
    instrument[local] = c.query_int(
        "INSERT INTO instruments(kind, model, serial, firmware, calibration) VALUES($1,$2,$3,$4,$5) "
        "ON CONFLICT(model, serial) DO UPDATE SET kind = excluded.kind RETURNING id",
        {in.kind, in.model, in.serial, in.firmware, in.calibration});
  std::map<std::int64_t, std::int64_t> channel;
  std::string copy;
  for (std::size_t i = 0; i < rc.channels.size(); ++i) {
    const Channel& ch = rc.channels[i];
    const auto server_channel = c.query_int(
        "INSERT INTO channels(run_id, name, unit, instrument_id, \"nominal_rate_Hz\") VALUES($1,$2,$3,$4,$5) "
        "RETURNING id",
        {id, ch.name, ch.unit,
         Param::id(instrument.count(ch.instrument_id) ? instrument[ch.instrument_id] : 0),
         ch.nominal_rate_Hz});
    channel[ch.id] = server_channel;
    copy.clear();
    for (const auto& s : rc.samples[i]) {
      pg::append_copy_value(copy, id);
      copy += '\t';
      pg::append_copy_value(copy, server_channel);
      copy += '\t';
      pg::append_copy_value(copy, s.t_ns);
      copy += '\t';
      pg::append_copy_value(copy, s.value);
      copy += '\t';
      pg::append_copy_value(copy, static_cast<std::int64_t>(s.segment));
      copy += '\n';
    }
    if (!copy.empty()) c.copy_in("COPY samples(run_id, channel_id, t_ns, value, segment) FROM STDIN", copy);
  }
  for (const auto& st : rc.steps) {
    const auto step = c.query_int(
        "INSERT INTO steps(run_id, step_index, target_displacement_mm, nominal_strain, "
        "\"target_pressure_kPa\", "
        "started_t_ns, settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed) "
        "VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11) RETURNING id",
        {id, st.index, st.target_displacement_mm, st.nominal_strain, st.target_pressure_kPa, st.started_t_ns,
         st.settled_t_ns, st.recorded_from_t_ns, st.recorded_to_t_ns, st.measured_transmission,
         st.completed ? 1 : 0});
    for (const auto& cs : st.channels)
      if (channel.count(cs.channel_id))
        c.query("INSERT INTO step_channel_stats(step_id, channel_id, mean, std, n) VALUES($1,$2,$3,$4,$5)",
                {step, channel[cs.channel_id], cs.mean, cs.std, cs.n});
  }
  for (const auto& e : rc.events)
    c.query(
        "INSERT INTO events(run_id, t_ns, kind, message, step_index, data_json, segment) "
        "VALUES($1,$2,$3,$4,$5,$6,$7)",
        {id, e.t_ns, e.kind, e.message, e.step_index >= 0 ? Param(e.step_index) : Param(std::nullopt),
         e.data_json.empty() ? Param(std::nullopt) : Param(e.data_json), e.segment});
  for (const auto& p : rc.predictions)
    c.query(
        "INSERT INTO predictions(run_id, step_index, config_json, \"T\", \"T_stderr\", fe_seconds, "
        "mesh_seconds, "
        "mc_seconds, total_seconds, software_version, summary_json, created_utc_ns, latency_s) "
        "VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13)",
        {id, p.step_index, p.config_json, p.T, p.T_stderr, p.fe_seconds, p.mesh_seconds, p.mc_seconds,
         p.total_seconds, p.software_version,
         p.summary_json.empty() ? Param(std::nullopt) : Param(p.summary_json), p.created_utc_ns,
         p.latency_s});
}

// One run in one transaction: the server shows it whole or not at all.
PushedRun push_one(const pg::Connection& c, const RunCopy& rc, const std::string& source) {
  const RunRecord& r = rc.run;
  PushedRun out{r.id, 0, r.uuid, std::string(to_string(r.status)), PushAction::copied, rc.sample_count};
  const std::string digest = rc.digest();
  pg::Transaction t(c);
  // A second push of the same run (another terminal, the post-run push) waits here, then
  // finds the run there.
  c.query("SELECT pg_advisory_xact_lock($1, hashtext($2))", {pg::kPushLockSpace, r.uuid});
  const pg::Result there = c.query(
      "SELECT r.id, p.source_digest, r.status FROM runs r LEFT JOIN pushed_runs p ON p.uuid = r.uuid "
      "WHERE r.uuid = $1",
      {r.uuid});
  std::int64_t id = 0;
  if (there.rows() > 0) {
    id = there.i64(0, 0);
    out.server_id = id;
    if (there.null(0, 1))
      throw DatabaseError(
          fmt::format("run {} ({}) is on the server as run {}, recorded there directly, not "
                      "pushed; it was left as it is",
                      r.id, r.uuid, id));
    if (there.text(0, 1) == digest) {
      out.action = PushAction::unchanged;
      return out;  // the transaction rolls back: nothing written
    }
    out.action = PushAction::updated;
    clear_run(c, id);
    c.query(
        "UPDATE runs SET name = $2, specimen_id = $3, protocol = $4, lab_config = $5, software_version = $6, "
        "operator = $7, \"baseline_power_W\" = $8, wall_anchor_utc_ns = $9, monotonic_anchor_ns = $10, "
        "started_utc_ns = $11, ended_utc_ns = $12, status = $13, host = $14, software_commit = $15 WHERE id "
        "= $1",
        {id, r.name, Param::id(rc.specimen ? server_specimen(c, *rc.specimen) : 0), r.protocol_text,
         r.lab_config_text, r.software_version, r.operator_name, r.baseline_power_W, r.wall_anchor_utc_ns,
         r.monotonic_anchor_ns, r.started_utc_ns,
         r.ended_utc_ns ? Param(*r.ended_utc_ns) : Param(std::nullopt), std::string(to_string(r.status)),
         r.host, r.software_commit});
  } else {
    id = c.query_int(
        "INSERT INTO runs(uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
        "\"baseline_power_W\", wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, ended_utc_ns, "
        "status, host, "
        "software_commit) VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13,$14,$15) RETURNING id",
        {r.uuid, r.name, Param::id(rc.specimen ? server_specimen(c, *rc.specimen) : 0), r.protocol_text,
         r.lab_config_text, r.software_version, r.operator_name, r.baseline_power_W, r.wall_anchor_utc_ns,
         r.monotonic_anchor_ns, r.started_utc_ns,
         r.ended_utc_ns ? Param(*r.ended_utc_ns) : Param(std::nullopt), std::string(to_string(r.status)),
         r.host, r.software_commit});
    out.server_id = id;
  }
  write_run_rows(c, rc, id);
  c.query(
      "INSERT INTO pushed_runs(uuid, source_digest, source, pushed_utc_ns) VALUES($1,$2,$3,$4) "
      "ON CONFLICT(uuid) DO UPDATE SET source_digest = excluded.source_digest, source = excluded.source, "
      "pushed_utc_ns = excluded.pushed_utc_ns",
      {r.uuid, digest, source, wall_clock_ns()});
  t.commit();
  return out;
}

}  // namespace

std::vector<PushedRun> push_runs(const std::filesystem::path& from, const std::string& to,
                                 const PushOptions& options) {
  if (!is_server_uri(to))
    throw DatabaseError(
        fmt::format("'{}' is not a PostgreSQL connection URI (postgresql://[user@]host[:port]/db)",
                    display_location(to)));
  if (is_server_uri(from.string()))
    throw DatabaseError("push copies from a local tocdlab file; '" + display_location(from.string()) +
                        "' is a server");
  const Reader local(from);
  const pg::Connection server(to);
  pg::ensure_schema(server);
  const std::string source = fmt::format("{}", from.string());
  std::vector<PushedRun> out;
  for (const auto& s : local.runs()) {
    PushedRun done;
    if (s.live) {
      done = {s.run.id, 0, s.run.uuid, "running", PushAction::skipped, 0};
    } else {
      try {
        done = push_one(server, read_run(local, s), source);
      } catch (const DatabaseError& e) {
        throw DatabaseError(
            fmt::format("run {} ({}) was not pushed, nothing of it is on the server: {}. {} run(s) "
                        "before it were pushed and stay; push again to continue",
                        s.run.id, s.run.uuid, e.what(), out.size()));
      }
    }
    if (options.on_run) options.on_run(done);
    out.push_back(std::move(done));
  }
  return out;
}

}  // namespace tocd::db
