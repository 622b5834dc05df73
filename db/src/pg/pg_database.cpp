#include "pg_database.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "backend_rows.hpp"
#include "pg_rows.hpp"
#include "pg_schema.hpp"
#include "resume_plan.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"

namespace tocd::db::pg {

PgDatabase::PgDatabase(const std::string& uri) : c_(uri) {
  ensure_schema(c_);
  mark_interrupted();
}

int PgDatabase::schema_version() const {
  std::lock_guard lk(mu_);
  return static_cast<int>(c_.query_int("SELECT value::int FROM meta WHERE key = 'schema_version'"));
}

std::string PgDatabase::integrity_check() const {
  std::lock_guard lk(mu_);
  const auto stray = c_.query_int(
      "SELECT count(*) FROM samples s LEFT JOIN channels ch ON ch.id = s.channel_id "
      "WHERE ch.id IS NULL OR ch.run_id <> s.run_id");
  return stray == 0 ? std::string("ok")
                    : fmt::format("{} sample(s) name a channel that is not in their run", stray);
}

bool PgDatabase::acquire(std::int64_t run_id) {
  if (held_.count(run_id)) return true;
  if (c_.query_int("SELECT pg_try_advisory_lock($1, $2::int)::int", {kLockSpace, run_id}) == 0) return false;
  held_.insert(run_id);
  return true;
}

void PgDatabase::release(std::int64_t run_id) {
  if (!held_.erase(run_id)) return;
  c_.query("SELECT pg_advisory_unlock($1, $2::int)", {kLockSpace, run_id});
}

bool PgDatabase::held(std::int64_t run_id) const {
  return held_.count(run_id) > 0 || run_locked(c_, run_id);
}

std::int64_t PgDatabase::insert_event(const EventRecord& e) {
  return c_.query_int(
      "INSERT INTO events(run_id, t_ns, kind, message, step_index, data_json, segment) "
      "VALUES($1,$2,$3,$4,$5,$6,"
      "(SELECT coalesce(max(segment), 0) FROM run_anchors WHERE run_id = $1)) RETURNING id",
      {e.run_id, e.t_ns, e.kind, e.message, e.step_index >= 0 ? Param(e.step_index) : Param(std::nullopt),
       e.data_json.empty() ? Param(std::nullopt) : Param(e.data_json)});
}

void PgDatabase::add_anchor(std::int64_t run_id, std::int64_t wall, std::int64_t mono, double clock_factor) {
  c_.query(
      "INSERT INTO run_anchors(run_id, segment, wall_utc_ns, monotonic_ns, clock_factor) VALUES($1, "
      "(SELECT coalesce(max(segment) + 1, 0) FROM run_anchors WHERE run_id = $1), $2, $3, $4)",
      {run_id, wall, mono, clock_factor});
}

void PgDatabase::mark_interrupted() {
  std::lock_guard lk(mu_);
  for (const auto& r : all_runs(c_)) {
    if (r.status != RunStatus::running || run_locked(c_, r.id)) continue;
    // Taking the lock proves no live session records the run, and keeps a second opener from
    // marking it twice.
    if (!acquire(r.id)) continue;
    Transaction t(c_);
    if (require_run(c_, r.id).status != RunStatus::running) {
      release(r.id);
      continue;
    }
    const detail::CutOff cut = detail::cut_off(r, run_anchors(c_, r.id), last_recorded_t_ns(c_, r.id));
    c_.query("UPDATE runs SET status = 'interrupted', ended_utc_ns = $1 WHERE id = $2",
             {cut.ended_utc_ns ? Param(*cut.ended_utc_ns) : Param(std::nullopt), r.id});
    insert_event(cut.event);
    t.commit();
    release(r.id);
    interrupted_.push_back(r.id);
    logger("db")->warn("run {} was left running; marked interrupted", r.id);
  }
}

std::int64_t PgDatabase::add_instrument(const InstrumentRecord& in) {
  std::lock_guard lk(mu_);
  return c_.query_int(
      "INSERT INTO instruments(kind, model, serial, firmware, calibration) VALUES($1,$2,$3,$4,$5) "
      "ON CONFLICT(model, serial) DO UPDATE SET kind = excluded.kind, firmware = excluded.firmware, "
      "calibration = excluded.calibration RETURNING id",
      {in.kind, in.model, in.serial, in.firmware, in.calibration});
}

std::int64_t PgDatabase::add_sample(const SampleRecord& sp) {
  std::lock_guard lk(mu_);
  return c_.query_int(
      "INSERT INTO specimens(name, tissue, thickness_mm, notes) VALUES($1,$2,$3,$4) RETURNING id",
      {sp.name, sp.tissue, sp.thickness_mm, sp.notes});
}

RunRecord PgDatabase::create_run(const NewRun&, const RunRecord& prepared) {
  std::lock_guard lk(mu_);
  RunRecord r = prepared;
  Transaction t(c_);
  r.id = c_.query_int(
      "INSERT INTO runs(uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
      "\"baseline_power_W\", wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, host, software_commit, "
      "status) VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13,'running') RETURNING id",
      {r.uuid, r.name, Param::id(r.sample_id), r.protocol_text, r.lab_config_text, r.software_version,
       r.operator_name, r.baseline_power_W, r.wall_anchor_utc_ns, r.monotonic_anchor_ns, r.started_utc_ns,
       r.host, r.software_commit});
  for (const auto& [key, value] : r.settings)
    c_.query("INSERT INTO run_settings(run_id, key, value) VALUES($1,$2,$3)", {r.id, key, value});
  add_anchor(r.id, r.wall_anchor_utc_ns, r.monotonic_anchor_ns, r.clock_factor);
  // Lock before commit: from the moment the run is visible as running, it is visibly live.
  if (!acquire(r.id)) throw DatabaseError(fmt::format("run {} is already locked by another process", r.id));
  t.commit();
  return r;
}

void PgDatabase::set_run_status(std::int64_t run_id, RunStatus status) {
  std::lock_guard lk(mu_);
  require_run(c_, run_id);
  c_.query("UPDATE runs SET status = $1, ended_utc_ns = $2 WHERE id = $3",
           {std::string(to_string(status)), wall_clock_ns(), run_id});
  release(run_id);
}

void PgDatabase::mark_run_ended(std::int64_t run_id) {
  std::lock_guard lk(mu_);
  require_run(c_, run_id);
  c_.query("UPDATE runs SET ended_utc_ns = $1 WHERE id = $2 AND status <> 'running'",
           {wall_clock_ns(), run_id});
}

void PgDatabase::set_baseline_power(std::int64_t run_id, double baseline_power_W) {
  std::lock_guard lk(mu_);
  require_run(c_, run_id);
  c_.query("UPDATE runs SET \"baseline_power_W\" = $1 WHERE id = $2", {baseline_power_W, run_id});
}

ResumePoint PgDatabase::resume_run(std::int64_t run_id, double clock_factor) {
  std::lock_guard lk(mu_);
  RunRecord r = require_run(c_, run_id);
  detail::require_resumable(r, [&] { return held(run_id); });
  if (!acquire(run_id))
    throw DatabaseError(fmt::format("run {} is being resumed by another process", run_id));
  try {
    Transaction t(c_);
    // As on a file: the gap, the new segment's start and its event (resume_plan.hpp).
    auto [p, wall] = rows::plan_resume_now(c_, r);
    add_anchor(run_id, wall, p.gap_to_t_ns, clock_factor);
    c_.query("UPDATE runs SET status = 'running', ended_utc_ns = NULL WHERE id = $1", {run_id});
    p.gap_event.id = insert_event(p.gap_event);
    t.commit();
    return detail::resumed(std::move(p), std::move(r));
  } catch (...) {
    release(run_id);
    throw;
  }
}

bool PgDatabase::is_live(std::int64_t run_id) const {
  std::lock_guard lk(mu_);
  return held(run_id);
}

Channel PgDatabase::add_channel(const Channel& ch) {
  std::lock_guard lk(mu_);
  require_run(c_, ch.run_id);
  Channel out = ch;
  try {
    out.id = c_.query_int(
        "INSERT INTO channels(run_id, name, unit, instrument_id, \"nominal_rate_Hz\") VALUES($1,$2,$3,$4,$5) "
        "RETURNING id",
        {ch.run_id, ch.name, ch.unit, Param::id(ch.instrument_id), ch.nominal_rate_Hz});
  } catch (const DatabaseError& e) {
    throw DatabaseError(fmt::format("cannot add channel '{}' to run {}: {}", ch.name, ch.run_id, e.what()));
  }
  return out;
}

std::int64_t PgDatabase::add_step(const StepRecord& st) {
  std::lock_guard lk(mu_);
  require_run(c_, st.run_id);
  Transaction t(c_);
  c_.query("DELETE FROM steps WHERE run_id = $1 AND step_index = $2",
           {st.run_id, st.index});  // stats cascade
  const auto id = c_.query_int(
      "INSERT INTO steps(run_id, step_index, target_displacement_mm, nominal_strain, "
      "\"target_pressure_kPa\", "
      "started_t_ns, settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed) "
      "VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11) RETURNING id",
      {st.run_id, st.index, st.target_displacement_mm, st.nominal_strain, st.target_pressure_kPa,
       st.started_t_ns, st.settled_t_ns, st.recorded_from_t_ns, st.recorded_to_t_ns, st.measured_transmission,
       st.completed ? 1 : 0});
  for (const auto& cs : st.channels) {
    try {
      c_.query("INSERT INTO step_channel_stats(step_id, channel_id, mean, std, n) VALUES($1,$2,$3,$4,$5)",
               {id, cs.channel_id, cs.mean, cs.std, cs.n});
    } catch (const DatabaseError& e) {
      throw DatabaseError(fmt::format("step {} of run {}: statistics for channel {}: {}", st.index, st.run_id,
                                      cs.channel_id, e.what()));
    }
  }
  t.commit();
  return id;
}

std::int64_t PgDatabase::add_event(const EventRecord& e) {
  std::lock_guard lk(mu_);
  try {
    return insert_event(e);
  } catch (const DatabaseError& err) {
    throw DatabaseError(fmt::format("cannot record event '{}' of run {}: {}", e.kind, e.run_id, err.what()));
  }
}

std::int64_t PgDatabase::add_prediction(const PredictionRecord& p) {
  std::lock_guard lk(mu_);
  require_run(c_, p.run_id);
  return c_.query_int(
      "INSERT INTO predictions(run_id, step_index, config_json, \"T\", \"T_stderr\", fe_seconds, "
      "mesh_seconds, "
      "mc_seconds, total_seconds, software_version, summary_json, created_utc_ns, latency_s) "
      "VALUES($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13) RETURNING id",
      {p.run_id, p.step_index, p.config_json, p.T, p.T_stderr, p.fe_seconds, p.mesh_seconds, p.mc_seconds,
       p.total_seconds, p.software_version.empty() ? std::string(tocd::version()) : p.software_version,
       p.summary_json.empty() ? Param(std::nullopt) : Param(p.summary_json),
       p.created_utc_ns != 0 ? p.created_utc_ns : wall_clock_ns(), p.latency_s});
}

int PgDatabase::first_incomplete_step(std::int64_t run_id) const {
  std::lock_guard lk(mu_);
  return pg::first_incomplete_step(c_, run_id);
}

RunRecord PgDatabase::run(std::int64_t run_id) const {
  std::lock_guard lk(mu_);
  return require_run(c_, run_id);
}

}  // namespace tocd::db::pg
